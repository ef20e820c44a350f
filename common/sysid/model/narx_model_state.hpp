#pragma once
// A NARX fuzzy model's whole state as plain data — regressor, scaling and one fuzzy model per
// output — which a model file (NarxModel::ToJson) and a bus snapshot (model_messages/) encode
// directly; NarxModel::FromState() is the one place either is checked.

#include <vector>

#include "fuzzy/fuzzy_model_state.hpp"
#include "sysid/model/data_envelope.hpp"
#include "sysid/model/output_limits.hpp"
#include "sysid/model/regressor_spec.hpp"
#include "sysid/model/scaling.hpp"

namespace odonata::sysid {

struct NarxModelState {
  RegressorSpec spec;
  Scaling scaling;
  OutputLimits limits;                         ///< empty: none
  DataEnvelope envelope;                       ///< empty: none
  std::vector<fuzzy::FuzzyModelState> models;  ///< one per output, in spec.outputs order
};

}  // namespace odonata::sysid
