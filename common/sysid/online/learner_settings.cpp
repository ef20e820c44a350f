#include "sysid/online/learner_settings.hpp"

namespace odonata::sysid {

nlohmann::ordered_json LearnerSettingsJson(const fuzzy::FuzzyModelConfig& model,
                                           const RefitSchedule& refit) {
  nlohmann::ordered_json j;
  j["consequent"] = fuzzy::ToString(model.consequent);
  j["entropy_threshold"] = model.entropy.threshold;
  j["max_rules"] = model.entropy.max_rules;
  j["kappa"] = model.entropy.kappa;
  j["sigma_init"] = model.entropy.sigma_init;
  j["sigma_min"] = model.entropy.sigma_min;
  j["sigma_max"] = model.entropy.sigma_max;
  j["forgetting"] = model.forgetting;
  j["prune_utility"] = model.entropy.prune_utility;
  j["prune_min_age"] = model.entropy.prune_min_age;
  // Refit with odonata-fit's learner on refit_buffer samples after refit_first learned, then 2×,
  // 4×, … up to refit_every, then every refit_every, and once more at a freeze (0: none;
  // docs/identifier.md §6.3). refit_history of the buffer keeps blocks spread over the whole run,
  // the rest the most recent samples. odonata-fit --refit-* replays the same schedule.
  j["refit_first"] = refit.first;
  j["refit_every"] = refit.every;
  j["refit_buffer"] = refit.buffer;
  j["refit_history"] = refit.history;
  j["refit_at_freeze"] = refit.at_freeze;
  j["refit_threads"] = refit.threads;
  // K >= 2: refits choose by the accuracy K samples ahead, for a loop that integrates (rates,
  // velocities), as odonata-fit --horizon K; 0: in free run.
  j["refit_horizon"] = refit.horizon;
  return j;
}

}  // namespace odonata::sysid
