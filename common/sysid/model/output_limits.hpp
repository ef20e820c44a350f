#pragma once
// Saturated outputs (docs/identifier.md §7.2). A level that overflows, a sensor that clips, an
// actuator at its stop: the measured output sits on one value for a stretch of the record. No
// model output beyond that value was ever observed, and a NARX model that predicts past it feeds
// the impossible value back as a lag in free run (the cascaded tanks: the linear model overshoots
// every overflow). Such a limit is found in the training data and every prediction is held to it.

#include <string>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace odonata::sysid {

struct OutputLimits {
  /// Per output, raw units; −∞ / +∞ where the output is not saturated. Empty: no limits.
  Eigen::VectorXd lower, upper;

  /// An output's extreme (its largest or smallest value) is a limit when the output holds it
  /// exactly for at least kMinRun samples in a row and on at least kMinShare of all samples: a
  /// noisy measurement reaches its extreme once, a saturated one stays there. `outputs` is rows ×
  /// outputs, in time order.
  static OutputLimits Detect(const Eigen::Ref<const Eigen::MatrixXd>& outputs);
  static constexpr int kMinRun = 5;
  static constexpr double kMinShare = 0.01;

  bool any() const;
  /// `y` held to the limits (a NaN stays NaN).
  double Apply(int output, double y) const {
    if (lower.size() == 0) return y;
    return y < lower(output) ? lower(output) : y > upper(output) ? upper(output) : y;
  }
  /// True when `y` is beyond a limit (Apply changed it).
  bool Holds(int output, double y) const {
    return lower.size() != 0 && (y < lower(output) || y > upper(output));
  }
  /// Sizes that differ from `outputs`, a lower limit above an upper one, a NaN; empty when fine.
  std::string Problems(int outputs) const;
  /// {"lower": [...], "upper": [...]}, null for an infinite side.
  nlohmann::json ToJson() const;
  static OutputLimits FromJson(const nlohmann::json& j, int outputs);
};

}  // namespace odonata::sysid
