#pragma once
// The stacked parameter vector of a simulation-error step, shared by the loss's normal equations
// (simulation_loss.cpp) and the trainer that applies the step (simulation_error_training.cpp):
// internal to estimation/.

#include <vector>

#include <Eigen/Core>

#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {

/// Where each output's parameters start in the stacked vector: its consequents, then (with
/// `premises`) its centres and its widths, rules × inputs each, column by column; the last entry
/// is the vector's length.
std::vector<Eigen::Index> ParameterOffsets(const NarxModel& model, bool premises);

}  // namespace odonata::sysid
