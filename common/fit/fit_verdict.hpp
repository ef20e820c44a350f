#pragma once
// The fit's verdict, the line a user reads first: the model's FIT in the mode it is judged by
// (K steps ahead with a horizon, else free run with output lags, else one step), on the
// validation file when there is one, beside ARX and persistence, and flagged when it says
// nothing: a constant model, or one below persistence (holding the last value does better).

#include <nlohmann/json.hpp>

#include "sysid/model/narx_model.hpp"

namespace odonata::fit {

/// {"data", "mode", "fit", "arx", "persistence", "flags": [...], "text"} for the first output of
/// `report` (its "validate" or "train" and "baselines" blocks); `model` and `series` (the data
/// the verdict is on) tell whether the model is a constant.
nlohmann::json Verdict(const nlohmann::json& report, const sysid::NarxModel& model,
                       const sysid::Series& series);

}  // namespace odonata::fit
