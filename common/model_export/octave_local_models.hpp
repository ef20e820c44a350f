#pragma once
// Each rule's linear local model for control design: a discrete state-space model per rule, as an
// Octave script that builds them as octave-control `ss` objects (Debian's octave-control), so a
// control engineer gets `pole`, `dcgain`, `step` and the rest of the toolbox on odonata's rules
// (docs/model_export.md §7).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sysid/model/narx_model.hpp"

namespace odonata::model_export {

/// The script: `local_models`, a struct array with one entry per rule of each output in
/// `outputs` (fields output, rule, A, B, C, D, Ts, offset, signals, sys, parameters, covariance),
/// y = C x + D v + offset about rest. `sample_time_s` 0: Ts = 1, time in samples. Numbers with
/// 17 digits, exact. `covariance`: the rule's parameter covariance in the order `parameters` names
/// ("1", then the regressor), from the model file's "local_model_covariance" (NarxModel::
/// SavedLocalCovariance; [] where the file holds none, or the rule stood for too few rows).
/// @pre the model's consequents are linear or singleton; outputs are indices of model outputs.
std::string OctaveLocalModels(const sysid::NarxModel& model, const std::vector<int>& outputs,
                              double sample_time_s, const std::string& source,
                              const nlohmann::json& covariance = nullptr);

}  // namespace odonata::model_export
