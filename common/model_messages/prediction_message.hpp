#pragma once
// The online identifier's report on one sample ⇄ prediction_t.

#include <cstdint>
#include <string>
#include <vector>

#include "odonata/prediction_t.hpp"
#include "sysid/online/online_identifier.hpp"

namespace odonata::model_messages {

/// `report` for outputs `names`, numbered `seq` and stamped `utime`.
/// @pre names.size() == report.measured.size().
odonata::prediction_t ToPredictionMessage(const sysid::SampleReport& report,
                                          const std::vector<std::string>& names, int64_t seq,
                                          int64_t utime);

}  // namespace odonata::model_messages
