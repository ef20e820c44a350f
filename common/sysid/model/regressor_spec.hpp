#pragma once
// The series-parallel (NARX) regressor of eq. 7: which lags of which signals feed the model.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace odonata::sysid {

/// Time series of one experiment, one row per sample (100 Hz in the paper). A recording with
/// gaps it could not bridge is several segments laid end to end (docs/identifier.md §7.1): no
/// regressor reaches across a break, and a free run starts again from measured values after one.
struct Series {
  Eigen::MatrixXd outputs;  ///< samples × outputs
  Eigen::MatrixXd inputs;   ///< samples × inputs
  /// Rows that start a new segment, increasing, each in (0, samples); empty for one segment.
  std::vector<Eigen::Index> breaks;
  Eigen::Index samples() const { return outputs.rows(); }
};

struct RegressorSpec;
/// The rows t with a complete regressor inside their own segment (t ≥ segment start +
/// first_target()), in order: the targets of BuildRegression, PredictOneStep and SimulateFreeRun.
std::vector<Eigen::Index> TargetRows(const RegressorSpec& spec, const Series& series);
/// The measured outputs at TargetRows (targets × outputs): what predictions are scored against.
Eigen::MatrixXd Targets(const RegressorSpec& spec, const Series& series);

/// x(t) = [y_o(t−1) … y_o(t−n) for each output o, u_i(t−d) … u_i(t−d−m+1) for each input i],
/// target y(t). With d = 1 and t = k+1 this is eq. 7: x(k) = [y(k) … y(k−n+1), u(k) … u(k−m+1)]
/// predicts y(k+1). With d = 0 the same row's inputs predict y(t); n = 0 then is static
/// regression. Several outputs share one regressor, each with its own model.
struct RegressorSpec {
  /// Bounds Problems() enforces, so a size computed from a spec never overflows and an absurd
  /// file or message is an error, not an allocation of terabytes.
  static constexpr int kMaxLags = 1000;
  static constexpr std::size_t kMaxSignals = 256;

  int output_lags = 1;  ///< n ≥ 0
  int input_lags = 1;   ///< m ≥ 0 (per input)
  int delay = 1;        ///< d ∈ {0, 1}
  std::vector<std::string> outputs;
  std::vector<std::string> inputs;

  int size() const;
  /// First target index with a complete regressor: max(n, d + m − 1).
  int first_target() const;
  /// Readable regressor names, e.g. "vz(k)", "vz(k-1)", "u(k)".
  std::vector<std::string> RegressorNames() const;
  /// The target's name, e.g. "vz(k+1)" (d = 1) or "vz(k)" (d = 0).
  std::string TargetName(int output) const;
  /// Lists every problem in one message (empty when valid), like fuzzylite's isReady.
  std::string Problems() const;

  /// Fills x with the regressor for target index t from `outputs` (samples × outputs, possibly
  /// the model's own predictions in free run) and `inputs`.
  /// @pre first_target() ≤ t < rows.
  void Fill(Eigen::Index t, const Eigen::Ref<const Eigen::MatrixXd>& outputs,
            const Eigen::Ref<const Eigen::MatrixXd>& inputs, Eigen::Ref<Eigen::VectorXd> x) const;
};

/// Regressors and targets of a whole series: the rows TargetRows() lists.
struct RegressionData {
  Eigen::MatrixXd x;  ///< rows × size()
  Eigen::MatrixXd y;  ///< rows × outputs
};

/// @throws std::invalid_argument when the series has no complete regressor.
RegressionData BuildRegression(const RegressorSpec& spec, const Series& series);

}  // namespace odonata::sysid
