#pragma once
// odonata-fit --track: the trained model run online over another record — learning on, beside a
// frozen copy and the ARX fitted on --train, each with the accuracy alarm — so a vehicle that
// changes mid-run shows what online learning is for (docs/identifier.md).

#include <string>

#include <nlohmann/json.hpp>

#include "sysid/model/arx_model.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::fit {

/// The tracking run of FitJobOptions::track_csv: one-step predictions of the model learning on
/// (online), of a frozen copy and of ARX, each with its accuracy alarm.
nlohmann::json Track(const sysid::RegressorSpec& spec, const sysid::Series& s,
                     const sysid::NarxModel& trained, const sysid::ArxModel& arx,
                     const std::string& output, int window, double forgetting);

}  // namespace odonata::fit
