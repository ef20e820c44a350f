#include "plant/trim_finder.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "plant/angle_constants.hpp"
#include "plant/dimav_plant.hpp"

namespace odonata::plant {
MeanLoad ComputeMeanLoadAtRest(const PlantConfig& config, const CommandMatrix& command,
                               int phase_samples) {
  const DimavPlant plant(config);
  MeanLoad mean;
  Eigen::Matrix<double, kWingCount, 3> per_wing;
  for (int k = 0; k < phase_samples; ++k) {
    const double phase = kTwoPi * k / phase_samples;
    const WingLoad load =
        plant.ComputeLoads(command, Eigen::Vector4d::Constant(phase), Eigen::Vector3d::Zero(),
                           Eigen::Vector3d::Zero(), &per_wing);
    mean.force_n += load.force_n;
    mean.moment_nm += load.moment_nm;
    mean.wing_force_x_n += per_wing.col(0);
    mean.wing_force_z_n += per_wing.col(2);
  }
  const double n = phase_samples;
  mean.force_n /= n;
  mean.moment_nm /= n;
  mean.wing_force_x_n /= n;
  mean.wing_force_z_n /= n;
  return mean;
}

TrimResult FindHoverTrim(const PlantConfig& config, const TrimOptions& options) {
  const int index =
      options.variable == TrimVariable::kFrequency ? kFlapFrequency : kStrokeAmplitude;
  const char* name = options.variable == TrimVariable::kFrequency ? "freq_hz" : "amp_rad";
  const double weight_n = config.mass_kg * config.gravity_mps2;
  CommandMatrix command = UniformCommand(config.nominal_command);
  double x = config.nominal_command(index);
  if (!(x > 0.0)) x = 0.5 * (config.limits.min(index) + config.limits.max(index));
  TrimResult result;
  for (int it = 1; it <= options.max_iterations; ++it) {
    command.col(index).setConstant(x);
    const MeanLoad load = ComputeMeanLoadAtRest(config, command, options.phase_samples);
    const double lift_n = load.force_n.z();
    if (!(lift_n > 0.0)) {
      throw std::runtime_error(std::string("hover trim: no lift at ") + name + " = " +
                               std::to_string(x));
    }
    if (std::fabs(lift_n - weight_n) <= options.tolerance_n) {
      if (x < config.limits.min(index) || x > config.limits.max(index)) {
        throw std::runtime_error(std::string("hover trim: ") + name + " = " + std::to_string(x) +
                                 " is outside the actuator limits");
      }
      result.command = command;
      result.freq_hz = command(0, kFlapFrequency);
      result.amp_rad = command(0, kStrokeAmplitude);
      result.mean_load = load;
      result.iterations = it;
      return result;
    }
    x *= std::sqrt(weight_n / lift_n);
  }
  throw std::runtime_error(std::string("hover trim: ") + name + " did not converge");
}

}  // namespace odonata::plant
