#include "sim_runner.hpp"

#include <cmath>
#include <stdexcept>

#include "experiments/sample_columns.hpp"
#include "io/csv_table.hpp"
#include "io/csv_writer.hpp"
#include "io/row_decimator.hpp"
#include "plant/output_signals.hpp"
#include "vehicle/vehicle_step.hpp"

namespace odonata::sim {

std::vector<std::string> CsvHeader(const std::vector<std::string>& extra_columns,
                                   bool applied_columns) {
  return experiments::SampleColumnNames(extra_columns, /*beat_averages=*/true, applied_columns);
}

SimResult RunAndWrite(const plant::PlantConfig& config, const experiments::ExperimentRun& run,
                      const std::string& output_path, int decimate) {
  plant::DimavPlant plant(config);
  plant.Reset(run.initial);
  const std::vector<std::string> header = CsvHeader(run.excitation_names, run.record_applied);
  io::CsvWriter writer(output_path, header);
  SimResult result;
  std::vector<double> row(header.size());
  // Decimation averages what holds over a sample (commands, excitation, applied channels) and
  // takes the rest at the block's first sample.
  std::vector<bool> is_input;
  for (const std::string& name : header) is_input.push_back(experiments::IsAveragedSignal(name));
  io::RowDecimator decimator(decimate, is_input);
  for (std::size_t k = 0; k < run.commands.size(); ++k) {
    const plant::PlantOutput o = plant.output();  // row k: the outputs at t_k, before the step
    const double t_s = static_cast<double>(k) * run.sample_period_s;
    const vehicle::VehicleStep step = vehicle::StepVehicle(
        plant, run.commands[k], run.attitude_hold, run.hold_gains, run.damage, t_s);
    // The command actually applied (hold added, clamped) is what the wings did, so that is what
    // is written; a damaged wing flies less, and the CSV keeps what was commanded.
    std::size_t c = 0;
    row[c++] = t_s;
    for (int w = 0; w < plant::kWingCount; ++w) {
      for (int i = 0; i < plant::kCommandsPerWing; ++i) row[c++] = step.applied(w, i);
    }
    for (const double v : plant::StateSignalValues(o)) row[c++] = v;
    for (const std::vector<double>& values : run.excitation_values) row[c++] = values[k];
    for (const double v : plant::BeatSignalValues(o.beat)) row[c++] = v;
    if (run.record_applied) {
      for (const double v : vehicle::AppliedChannelValues(step.applied, run.trim.amp_rad)) {
        row[c++] = v;
      }
    }
    if (const auto block = decimator.Push(static_cast<int64_t>(k), row)) {
      writer.WriteRow(*block);
      ++result.rows_written;
    }
    if (step.status == plant::StepStatus::kReset) {
      ++result.resets;
      result.messages.push_back(plant.divergence_message());
    } else if (step.status == plant::StepStatus::kStopped) {
      result.stopped = true;
      result.messages.push_back(plant.divergence_message());
      break;
    }
  }
  writer.Close();
  return result;
}

experiments::ExperimentRun ReadCommandFile(const std::string& path,
                                           const plant::PlantConfig& config,
                                           double start_altitude_m) {
  const io::CsvTable table = io::CsvTable::Read(path);
  const std::vector<double>& t = table.Column("t_s");
  std::vector<const std::vector<double>*> columns;
  for (int w = 0; w < plant::kWingCount; ++w) {
    for (int i = 0; i < plant::kCommandsPerWing; ++i) {
      columns.push_back(&table.Column(plant::CommandColumnName(w, i)));
    }
  }
  if (table.rows() == 0) throw std::runtime_error(path + ": no command rows");
  const double dt_s = 1.0 / config.integration.sample_rate_hz;
  for (std::size_t k = 1; k < t.size(); ++k) {
    if (std::fabs((t[k] - t[k - 1]) - dt_s) > 1e-6) {
      throw std::runtime_error(path + ": t_s must advance by the sample period " +
                               std::to_string(dt_s) + " s; row " + std::to_string(k + 1) +
                               " advances by " + std::to_string(t[k] - t[k - 1]) + " s");
    }
  }
  experiments::ExperimentRun run;
  run.sample_period_s = dt_s;
  run.commands.resize(table.rows());
  for (std::size_t k = 0; k < table.rows(); ++k) {
    for (int w = 0; w < plant::kWingCount; ++w) {
      for (int i = 0; i < plant::kCommandsPerWing; ++i) {
        run.commands[k](w, i) = (*columns[w * plant::kCommandsPerWing + i])[k];
      }
    }
  }
  // The vehicle starts at rest, level, at the requested height, with the wings already flapping
  // with the first command (so the wing-beat averages are meaningful from the first row).
  run.initial.state.position_m = Eigen::Vector3d(0.0, 0.0, start_altitude_m);
  run.initial.prior_command = run.commands.front();
  return run;
}

}  // namespace odonata::sim
