#include "experiments/sample_columns.hpp"

#include "experiments/experiment_preset.hpp"
#include "plant/output_signals.hpp"
#include "plant/wing_command.hpp"

namespace odonata::experiments {

const std::vector<std::string>& CommandSignalNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (int w = 0; w < plant::kWingCount; ++w)
      for (int i = 0; i < plant::kCommandsPerWing; ++i) n.push_back(plant::CommandColumnName(w, i));
    return n;
  }();
  return names;
}

std::vector<std::string> SampleColumnNames(const std::vector<std::string>& excitation_names,
                                           bool beat_averages, bool applied_channels) {
  std::vector<std::string> h = {"t_s"};
  const auto add = [&h](const std::vector<std::string>& names) {
    h.insert(h.end(), names.begin(), names.end());
  };
  add(CommandSignalNames());
  add(plant::StateSignalNames());
  add(excitation_names);
  if (beat_averages) add(plant::BeatSignalNames());
  if (applied_channels) add(vehicle::AppliedChannelNames());
  return h;
}

bool IsAveragedSignal(const std::string& name) {
  if (name == "t_s" || name == "window_s") return false;
  if (plant::StateSignalIndex(name) || plant::BeatSignalIndex(name)) return false;
  return true;  // commands, applied channels and any excitation name
}

}  // namespace odonata::experiments
