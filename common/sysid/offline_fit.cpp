#include "sysid/offline_fit.hpp"

#include <algorithm>

namespace odonata::sysid {

OfflineFit FitOffline(
    const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& config, const TrainOptions& train,
    const Series& series, const OfflineFitOptions& options,
    const std::function<void(const Candidate&, std::size_t, std::size_t)>& on_candidate,
    const Series* selection_series) {
  fuzzy::FuzzyModelConfig cfg = config;
  TrainOptions topt = train;
  if (options.scaling) topt.fit_scaling = false;
  std::optional<SelectionResult> sel;
  if (options.search) {
    SelectionOptions so = options.selection;
    so.scaling = options.scaling;
    if (!topt.refine_least_squares) so.simulation.clear();  // the online pass has no such phase
    sel = SelectModel(spec, cfg, topt, series, so, on_candidate, selection_series);
    const Candidate& c = sel->candidates[sel->chosen];
    cfg = CandidateConfig(cfg, c);
    topt.simulation = c.simulation;
    if (!options.epochs_given) topt.epochs = std::max(1, c.epochs);
  }
  if (options.on_training) options.on_training(topt.epochs);
  // The chosen setting, refitted on the whole series (the hold-out included).
  NarxModel model(spec, cfg);
  if (options.scaling) model.SetScaling(*options.scaling);
  TrainReport report = model.Train(series, topt);
  return OfflineFit{std::move(model), cfg, topt, std::move(sel), std::move(report)};
}

}  // namespace odonata::sysid
