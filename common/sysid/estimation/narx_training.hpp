#pragma once
// The offline estimation of a NARX model (docs/identifier.md §3): one-step passes that grow and
// tune the rules, least squares on the consequents, then iRprop− on the multiple-shooting
// simulation error (simulation_error_training.hpp).

#include "sysid/estimation/train_options.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {

/// Trains `model` on `train`: FitScaling (unless options.fit_scaling is false), then up to
/// `epochs` passes (+ least squares if asked), each accepted only if it lowers the training loss.
TrainReport Train(NarxModel& model, const Series& train, const TrainOptions& options);

/// Sets a model's parts that only a whole training may set (NarxModel befriends it).
class NarxTrainer {
 public:
  static TrainReport Train(NarxModel& model, const Series& train, const TrainOptions& options);
};

}  // namespace odonata::sysid
