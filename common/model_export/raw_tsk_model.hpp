#pragma once
// A NARX model's output folded into one Takagi–Sugeno model in raw units: the scaling
// (sysid/scaling.hpp), the width floor ε and the output widths become plain Gaussian centres,
// widths, rule weights and coefficients (docs/model_export.md §1), so a client that knows
// nothing of odonata (evalfis, fuzzylite, inference/odonata/tsk_model.hpp) gives its outputs.

#include <string>
#include <vector>

#include "odonata/tsk_model.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::model_export {

/// `name` as an identifier every client accepts: "vz(k-1)" → "vz_km1", "vz(k+1)" → "vz_kp1".
std::string ClientName(const std::string& name);

/// Output `output` of `model` in raw units; inputs are the regressor, in spec().RegressorNames()
/// order. @throws std::invalid_argument when the output does not exist or has no rule.
inference::TskModel ToRawTsk(const sysid::NarxModel& model, int output,
                             const std::string& name = "odonata");

}  // namespace odonata::model_export
