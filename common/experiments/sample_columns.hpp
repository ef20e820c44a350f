#pragma once
// The columns of a sample, in the order odonata-sim writes them and odonata-logger export writes
// a recorded run, so one file format serves both and odonata-fit reads either:
//   t_s, the 24 commands (w{i}_beta_rad … w{i}_phase_rad), the plant's outputs
//   (plant::StateSignalNames()), the excitation, the beat averages (plant::BeatSignalNames())
//   and the applied-command channels (AppliedChannelNames()).
// New columns go after the old ones, so every column keeps its place.

#include <string>
#include <vector>

namespace odonata::experiments {

/// "w1_beta_rad" … "w4_phase_rad" (plant::CommandColumnName order).
const std::vector<std::string>& CommandSignalNames();

std::vector<std::string> SampleColumnNames(const std::vector<std::string>& excitation_names,
                                           bool beat_averages, bool applied_channels);

/// True for a signal that holds over [t_k, t_k+1) — a command, an excitation, an applied
/// channel — which decimation averages over a block; false for a measurement at t_k (an output,
/// a beat average, "t_s", "window_s"), which it takes at the block's first sample.
bool IsAveragedSignal(const std::string& name);

}  // namespace odonata::experiments
