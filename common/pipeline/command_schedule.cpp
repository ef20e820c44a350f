#include "pipeline/command_schedule.hpp"

#include <cmath>
#include <stdexcept>

#include "io/csv_table.hpp"
#include "pipeline/vehicle_setup.hpp"
#include "vehicle/command_limits.hpp"

namespace odonata::pipeline {
namespace {
// Problems listed before an error message is cut short.
constexpr int kMaxListedProblems = 10;
}  // namespace

CommandSchedule PresetSchedule(const experiments::ExperimentPreset& preset,
                               experiments::Phase phase, std::uint64_t seed, double duration_s,
                               const plant::PlantConfig& config) {
  experiments::ExperimentRun run =
      experiments::BuildExperimentRun(preset, phase, seed, duration_s, config);
  if (run.commands.empty()) {
    throw std::runtime_error("preset " + preset.name + ": the run has no samples (duration " +
                             std::to_string(duration_s) + " s)");
  }
  CommandSchedule s;
  s.commands = std::move(run.commands);
  s.excitation_names = std::move(run.excitation_names);
  s.excitation_values = std::move(run.excitation_values);
  s.sample_period_s = run.sample_period_s;
  s.source = "preset:" + preset.name + "/" + experiments::PhaseName(phase);
  s.setup_name = SetupName(preset, phase);
  return s;
}

CommandSchedule FileSchedule(const std::string& path, const plant::PlantConfig& config,
                             double duration_s) {
  const io::CsvTable table = io::CsvTable::Read(path);
  CommandSchedule s;
  s.source = path;
  s.sample_period_s = 1.0 / config.integration.sample_rate_hz;
  std::size_t rows = table.rows();
  if (duration_s > 0.0) {
    rows = std::min(rows, static_cast<std::size_t>(duration_s / s.sample_period_s + 0.5));
  }
  if (rows == 0) throw std::runtime_error(path + ": no command rows");

  std::string problems;
  int listed = 0;
  const auto problem = [&](const std::string& text) {
    if (listed++ < kMaxListedProblems) problems += "\n  " + text;
  };
  const std::vector<double>& t = table.Column("t_s");
  for (std::size_t k = 1; k < rows; ++k) {
    if (std::fabs((t[k] - t[k - 1]) - s.sample_period_s) > 1e-6) {
      problem("sample " + std::to_string(k) + ": t_s advances by " +
              std::to_string(t[k] - t[k - 1]) + " s, not the sample period " +
              std::to_string(s.sample_period_s) + " s");
    }
  }
  std::vector<const std::vector<double>*> columns;
  for (int w = 0; w < plant::kWingCount; ++w) {
    for (int i = 0; i < plant::kCommandsPerWing; ++i) {
      columns.push_back(&table.Column(plant::CommandColumnName(w, i)));
    }
  }
  s.commands.resize(rows);
  for (std::size_t k = 0; k < rows; ++k) {
    for (int w = 0; w < plant::kWingCount; ++w) {
      for (int i = 0; i < plant::kCommandsPerWing; ++i) {
        s.commands[k](w, i) = (*columns[w * plant::kCommandsPerWing + i])[k];
      }
    }
    const std::string limits = vehicle::CommandLimitProblems(s.commands[k], config.limits);
    if (!limits.empty()) problem("sample " + std::to_string(k) + ": " + limits);
  }
  if (listed > 0) {
    if (listed > kMaxListedProblems) {
      problems += "\n  … and " + std::to_string(listed - kMaxListedProblems) + " more";
    }
    throw std::runtime_error(path + ": " + std::to_string(listed) + " problem(s):" + problems);
  }
  for (const std::string& name : table.names()) {
    if (name.rfind("u_", 0) != 0) continue;
    const std::vector<double>& v = table.Column(name);
    s.excitation_names.push_back(name);
    s.excitation_values.emplace_back(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(rows));
  }
  return s;
}

}  // namespace odonata::pipeline
