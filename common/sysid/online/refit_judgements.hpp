#pragma once
// The judgements that decide what a scheduled refit lands (docs/identifier.md §6.3): the
// incumbent against the new choice, a reused setting's model against a selection's checks, an
// expert's rules against the choice, the linear model against the fuzzy one on the samples that
// came in while the refit ran.

#include <optional>

#include "sysid/model/narx_model.hpp"
#include "sysid/model/regressor_spec.hpp"
#include "sysid/model/sample.hpp"
#include "sysid/selection/model_selection.hpp"

namespace odonata::sysid {

/// The selection's linear candidate, if it had one.
std::optional<Candidate> LinearCandidate(const SelectionResult& selection);
/// The rest deviation a model is held to: the free-run criterion's linear candidate's (NaN: none).
double LinearRest(const SelectionResult& selection);
/// The linear candidate beside a fuzzy choice, to train with each refit; none when the choice is
/// the linear model.
std::optional<Candidate> LinearBeside(const SelectionResult& selection);

/// A selecting refit keeps the model the last refit landed (the incumbent) when, on the refit's
/// hold-out slice — its newest samples, unseen by both — the incumbent beats the candidate the
/// selection chose by the margin a candidate needs over a simpler one (docs/identifier.md §6.3):
/// a selection on one buffer can fall back to the linear model because its fuzzy candidates ran
/// away on one cross-validation fold, while the model learned from earlier buffers still
/// predicts the newest samples three times better.
bool IncumbentHoldsItsOwn(const NarxModel& incumbent, const SelectionResult& selection,
                          const Series& series, const SelectionOptions& options);

/// A refit that trained with the last selection's setting (steady state: no search, so no
/// hold-out) lands only when its model passes, on the samples kept, the checks that selection
/// held its model to (docs/identifier.md §6.3): a finite score by its criterion
/// (`criterion_horizon`, 0 free run) and, with `linear_rest` finite (the free-run criterion's
/// linear candidate), at rest where the linear model is. The incumbent is held to the same.
bool SteadyStateHolds(const NarxModel& model, const Series& series, int criterion_horizon,
                      double linear_rest);

/// `expert`'s rules with every consequent refitted by least squares on `series` (premises as
/// they are; the expert's scaling): the expert's local models refined on the vehicle's samples.
NarxModel RefineExpert(const NarxModel& expert, const Series& series);

/// The refit's own choice replaces an expert's rules only when it beats them — refined on the
/// selection's fit slice — on its hold-out by the margin a candidate needs over a simpler one
/// (false: they stay). A search on blocks of a longer buffer has no such slice: they stay.
bool ExpertHoldsItsOwn(const NarxModel& expert, const SelectionResult& selection,
                       const Series& series, const SelectionOptions& options);

/// At a landing, the samples that came in while the refit ran are ones neither the refit's
/// fuzzy model nor the linear model trained beside it (on the same samples) has seen: the linear
/// model lands instead when, on them, it beats the fuzzy one by the margin a candidate needs over
/// a simpler one, by the refit's criterion (`criterion_horizon`, 0 free run; docs/identifier.md
/// §6.3). A fuzzy model that runs away there loses to a linear one that does not.
bool LinearWinsTheNewSamples(const NarxModel& fuzzy, const NarxModel& linear, const Series& fresh,
                             int criterion_horizon);
/// K steps ahead, that judgement scores every (K / this)-th target only.
inline constexpr int kLandingCheckStrideDivisor = 10;

}  // namespace odonata::sysid
