#pragma once
// The learner's settings as an identifier configuration writes them (odonata-identifier --config,
// docs/identifier.md §5): the entropy fuzzy model's and the scheduled refits'. One writer for
// every configuration odonata writes — odonata-identifier --print-config and odonata-fit
// --save-config — so a setting added to the learner cannot be left out of one of them.

#include <nlohmann/json.hpp>

#include "fuzzy/fuzzy_model.hpp"
#include "sysid/online/scheduled_refitter.hpp"

namespace odonata::sysid {

/// consequent, entropy_threshold, max_rules, kappa, sigma_init, sigma_min, sigma_max,
/// forgetting, prune_utility, prune_min_age, then refit_first, refit_every, refit_buffer,
/// refit_history, refit_at_freeze, refit_threads and refit_horizon, in that order.
nlohmann::ordered_json LearnerSettingsJson(const fuzzy::FuzzyModelConfig& model,
                                           const RefitSchedule& refit);

}  // namespace odonata::sysid
