#pragma once
// What a control engineer reads from a linear local model: its poles, whether it is stable, its
// time constants and damping, and its steady-state gain from each input. Each rule of a model
// with linear consequents is an ARX model in raw units, y(t) = c + Σ a_l y(t−l) + Σ b_il u_i(…):
// its poles are the roots of z^n − a_1 z^(n−1) − … − a_n, its gain from u_i is Σ_l b_il / (1 − Σ
// a_l) (docs/identifier.md §7.4). With several outputs, the other outputs' lags count as inputs.

#include <complex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {

/// ŷ = constant + coefficientsᵀ x, raw units, over the spec's regressor.
struct RawLinearModel {
  double constant = 0;
  Eigen::VectorXd coefficients;
};

/// Rule `rule` of output `output` in raw units (a singleton rule is a constant).
RawLinearModel RuleLinearModel(const NarxModel& model, int output, int rule);
/// The scaled linear model θ = [a0; a_1 … a_N] of `output` in raw units.
RawLinearModel ScaledToRaw(const Scaling& scaling, int output, const Eigen::VectorXd& theta);
/// The model's global linear model (its data envelope's, docs/identifier.md §7.3), if it has one.
std::optional<RawLinearModel> GlobalLinearModel(const NarxModel& model, int output);

struct LocalDynamics {
  std::vector<std::complex<double>> poles;  ///< z-plane, the output's own lags; none if n = 0
  bool stable = true;                       ///< every pole inside the unit circle
  /// Per pole: −T / ln|p| in seconds (in samples when T is 0): the decay time, negative when the
  /// pole grows, 0 for a pole at the origin (gone in one step).
  std::vector<double> time_constants;
  /// Per pole: the damping ratio of the continuous pole s = ln(p)/T (1 for a positive real pole,
  /// below 1 for a complex or negative one).
  std::vector<double> damping;
  /// Per input signal (the other outputs' too): the steady-state gain; NaN with a pole at 1.
  std::vector<std::pair<std::string, double>> dc_gain;
  double equilibrium = 0;  ///< the output at rest with every input 0: c / (1 − Σ a_l)
};

/// `sample_time_s` 0: time constants in samples.
LocalDynamics AnalyseDynamics(const RegressorSpec& spec, int output, const RawLinearModel& model,
                              double sample_time_s);

/// Every rule of `output`, in order.
std::vector<LocalDynamics> LocalModels(const NarxModel& model, int output, double sample_time_s);

/// {"poles": [[re, im]…], "stable", "time_constants_s" (or "_samples"), "damping", "dc_gain":
/// {input: gain}, "equilibrium"}.
nlohmann::json ToJson(const LocalDynamics& d, double sample_time_s);

/// A linear local model as a discrete state-space model x(t+1) = A x(t) + B v(t), y(t) = C x(t) +
/// D v(t) about rest (the constant left out: `offset` adds it, y = … + offset), v the exogenous
/// signals (the other outputs, then the inputs, `signals`). The state is a shift register of the
/// output's own lags and each signal's lags, so A's eigenvalues are the poles of AnalyseDynamics
/// and one pole at 0 per delayed input sample; the gains and step responses are the model's.
struct LocalStateSpace {
  Eigen::MatrixXd a, b, c, d;
  std::vector<std::string> signals;
  double offset = 0;
};
LocalStateSpace StateSpace(const RegressorSpec& spec, int output, const RawLinearModel& model);
/// The model's response to a unit step on signal `signal` from rest (constant left out), samples
/// 0 … steps−1, by its own recursion (no state-space detour): what StateSpace must reproduce.
std::vector<double> StepResponse(const RegressorSpec& spec, int output, const RawLinearModel& model,
                                 int signal, int steps);

/// A number as the rules' sentences print it: three significant digits ("0.0561", "1.05e+03").
std::string SentenceNumber(double v);

/// "τ 0.12 s, gain 31 from m2, 2.1 from thrust": the slowest pole's time constant (with its
/// damping when it oscillates) and the gains, for a rule's sentence.
std::string DescribeDynamics(const LocalDynamics& d, double sample_time_s);

}  // namespace odonata::sysid
