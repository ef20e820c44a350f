#include "sim_runner.hpp"

#include <cmath>
#include <stdexcept>

#include "io/csv_table.hpp"
#include "io/csv_writer.hpp"
#include "io/row_decimator.hpp"

namespace odonata::sim {

const std::vector<std::string>& BeatColumnNames() {
  static const std::vector<std::string> kNames = {"vx_mps_avg",     "vy_mps_avg",    "vz_mps_avg",
                                                  "p_radps_avg",    "q_radps_avg",   "r_radps_avg",
                                                  "roll_rad_avg",   "pitch_rad_avg", "yaw_rad_avg",
                                                  "fx_total_n_avg", "fz_total_n_avg"};
  return kNames;
}

std::vector<std::string> CsvHeader(const std::vector<std::string>& extra_columns,
                                   bool applied_columns) {
  std::vector<std::string> h = {"t_s"};
  for (int w = 0; w < plant::kWingCount; ++w) {
    for (int i = 0; i < plant::kCommandsPerWing; ++i) h.push_back(plant::CommandColumnName(w, i));
  }
  for (const char* name : {"vx_mps", "vy_mps", "vz_mps", "p_radps", "q_radps", "r_radps",
                           "roll_rad", "pitch_rad", "yaw_rad", "x_m", "y_m", "z_m"}) {
    h.push_back(name);
  }
  for (int w = 1; w <= plant::kWingCount; ++w) h.push_back("fx" + std::to_string(w) + "_n");
  for (int w = 1; w <= plant::kWingCount; ++w) h.push_back("fz" + std::to_string(w) + "_n");
  h.insert(h.end(), extra_columns.begin(), extra_columns.end());
  h.insert(h.end(), BeatColumnNames().begin(), BeatColumnNames().end());
  if (applied_columns) {
    const std::vector<std::string>& applied = experiments::AppliedChannelNames();
    h.insert(h.end(), applied.begin(), applied.end());
  }
  return h;
}

SimResult RunAndWrite(const plant::PlantConfig& config, const experiments::ExperimentRun& run,
                      const std::string& output_path, int decimate) {
  plant::DimavPlant plant(config);
  plant.Reset(run.initial);
  const std::vector<std::string> header = CsvHeader(run.excitation_names, run.record_applied);
  io::CsvWriter writer(output_path, header);
  SimResult result;
  std::vector<double> row(header.size());
  // Decimation: inputs (commands, excitation, applied channels) are averaged over a block, the
  // rest is taken at the block's first sample.
  std::vector<bool> is_input(header.size(), false);
  const std::size_t commands = plant::kWingCount * plant::kCommandsPerWing;
  const std::size_t first_excitation = 1 + commands + 12 + 2 * plant::kWingCount;  // after fz4_n
  for (std::size_t c = 1; c <= commands; ++c) is_input[c] = true;
  for (std::size_t e = 0; e < run.excitation_names.size(); ++e)
    is_input[first_excitation + e] = true;
  if (run.record_applied) {
    for (std::size_t c = header.size() - experiments::AppliedChannelNames().size();
         c < header.size(); ++c) {
      is_input[c] = true;
    }
  }
  io::RowDecimator decimator(decimate, is_input);
  for (std::size_t k = 0; k < run.commands.size(); ++k) {
    const plant::PlantOutput& o = plant.output();
    // The command actually applied (clamped) is what the wings did, so that is what is written.
    const plant::CommandMatrix command = plant.ClampToLimits(
        run.attitude_hold ? experiments::ApplyAttitudeHold(run.hold_gains, run.commands[k], o)
                          : run.commands[k]);
    std::size_t c = 0;
    row[c++] = static_cast<double>(k) * run.sample_period_s;
    for (int w = 0; w < plant::kWingCount; ++w) {
      for (int i = 0; i < plant::kCommandsPerWing; ++i) row[c++] = command(w, i);
    }
    for (int i = 0; i < 3; ++i) row[c++] = o.velocity_body_mps(i);
    for (int i = 0; i < 3; ++i) row[c++] = o.rate_body_radps(i);
    row[c++] = o.roll_rad;
    row[c++] = o.pitch_rad;
    row[c++] = o.yaw_rad;
    for (int i = 0; i < 3; ++i) row[c++] = o.position_m(i);
    for (int w = 0; w < plant::kWingCount; ++w) row[c++] = o.force_x_n(w);
    for (int w = 0; w < plant::kWingCount; ++w) row[c++] = o.force_z_n(w);
    for (const std::vector<double>& values : run.excitation_values) row[c++] = values[k];
    const plant::BeatAverages& b = o.beat;
    for (int i = 0; i < 3; ++i) row[c++] = b.velocity_body_mps(i);
    for (int i = 0; i < 3; ++i) row[c++] = b.rate_body_radps(i);
    row[c++] = b.roll_rad;
    row[c++] = b.pitch_rad;
    row[c++] = b.yaw_rad;
    row[c++] = b.force_x_n;
    row[c++] = b.force_z_n;
    if (run.record_applied) {
      for (const double v : experiments::AppliedChannelValues(command, run.trim.amp_rad)) {
        row[c++] = v;
      }
    }
    if (const auto block = decimator.Push(static_cast<int64_t>(k), row)) {
      writer.WriteRow(*block);
      ++result.rows_written;
    }

    // A damaged wing flies less than it is told; the CSV keeps what was commanded.
    const plant::StepStatus status =
        plant.Step(run.damage.Apply(command, double(k) * run.sample_period_s));
    if (status == plant::StepStatus::kReset) {
      ++result.resets;
      result.messages.push_back(plant.divergence_message());
    } else if (status == plant::StepStatus::kStopped) {
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
