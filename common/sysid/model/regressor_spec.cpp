#include "sysid/model/regressor_spec.hpp"

#include <algorithm>
#include <stdexcept>
#include "contract/precondition.hpp"

namespace odonata::sysid {
namespace {
std::string Lag(const std::string& name, int offset) {
  if (offset == 0) return name + "(k)";
  return name + "(k" + (offset > 0 ? "+" : "-") + std::to_string(std::abs(offset)) + ")";
}
}  // namespace

int RegressorSpec::size() const {
  return static_cast<int>(outputs.size()) * output_lags +
         static_cast<int>(inputs.size()) * input_lags;
}

int RegressorSpec::first_target() const { return std::max(output_lags, delay + input_lags - 1); }

std::vector<std::string> RegressorSpec::RegressorNames() const {
  // Name lags relative to k, where the target is k+1 for d = 1 and k for d = 0.
  std::vector<std::string> names;
  const int target = delay == 1 ? 1 : 0;
  for (const auto& o : outputs)
    for (int l = 1; l <= output_lags; ++l) names.push_back(Lag(o, target - l));
  for (const auto& u : inputs)
    for (int l = 0; l < input_lags; ++l) names.push_back(Lag(u, target - delay - l));
  return names;
}

std::string RegressorSpec::TargetName(int output) const {
  return Lag(outputs.at(static_cast<std::size_t>(output)), delay == 1 ? 1 : 0);
}

std::string RegressorSpec::Problems() const {
  std::string p;
  auto add = [&p](const std::string& s) { p += (p.empty() ? "" : "; ") + s; };
  if (outputs.empty()) add("no output signal");
  if (output_lags < 0 || output_lags > kMaxLags)
    add("output lags must be in [0, " + std::to_string(kMaxLags) + "]");
  if (input_lags < 0 || input_lags > kMaxLags)
    add("input lags must be in [0, " + std::to_string(kMaxLags) + "]");
  if (outputs.size() > kMaxSignals || inputs.size() > kMaxSignals)
    add("at most " + std::to_string(kMaxSignals) + " outputs and " + std::to_string(kMaxSignals) +
        " inputs");
  if (delay != 0 && delay != 1) add("delay must be 0 or 1");
  if (input_lags > 0 && inputs.empty()) add("input lags given but no input signal");
  if (!p.empty()) return p;  // size() is only meaningful (and overflow-free) within the bounds
  if (size() == 0) add("the regressor is empty (no output lags and no input lags)");
  return p;
}

void RegressorSpec::Fill(Eigen::Index t, const Eigen::Ref<const Eigen::MatrixXd>& y,
                         const Eigen::Ref<const Eigen::MatrixXd>& u,
                         Eigen::Ref<Eigen::VectorXd> x) const {
  // Counts come from the spec, never from the matrices: a series with extra columns must not
  // write past the end of x.
  ODONATA_EXPECTS(y.cols() >= static_cast<Eigen::Index>(outputs.size()));
  ODONATA_EXPECTS(u.cols() >= static_cast<Eigen::Index>(inputs.size()));
  ODONATA_EXPECTS(x.size() == size());
  Eigen::Index c = 0;
  for (std::size_t o = 0; o < outputs.size(); ++o)
    for (int l = 1; l <= output_lags; ++l) x(c++) = y(t - l, static_cast<Eigen::Index>(o));
  for (std::size_t i = 0; i < inputs.size(); ++i)
    for (int l = 0; l < input_lags; ++l) x(c++) = u(t - delay - l, static_cast<Eigen::Index>(i));
}

std::vector<Eigen::Index> TargetRows(const RegressorSpec& spec, const Series& series) {
  std::vector<Eigen::Index> rows;
  const Eigen::Index t0 = spec.first_target();
  Eigen::Index start = 0;
  std::size_t b = 0;
  for (Eigen::Index t = 0; t < series.samples(); ++t) {
    if (b < series.breaks.size() && t == series.breaks[b]) {
      start = t;
      ++b;
    }
    if (t >= start + t0) rows.push_back(t);
  }
  return rows;
}

Eigen::MatrixXd Targets(const RegressorSpec& spec, const Series& series) {
  const auto rows = TargetRows(spec, series);
  Eigen::MatrixXd y(static_cast<Eigen::Index>(rows.size()), series.outputs.cols());
  for (std::size_t r = 0; r < rows.size(); ++r)
    y.row(static_cast<Eigen::Index>(r)) = series.outputs.row(rows[r]);
  return y;
}

RegressionData BuildRegression(const RegressorSpec& spec, const Series& series) {
  if (series.outputs.cols() != static_cast<Eigen::Index>(spec.outputs.size()) ||
      series.inputs.cols() != static_cast<Eigen::Index>(spec.inputs.size())) {
    throw std::invalid_argument(
        "series has " + std::to_string(series.outputs.cols()) + " outputs and " +
        std::to_string(series.inputs.cols()) + " inputs, the regressor expects " +
        std::to_string(spec.outputs.size()) + " and " + std::to_string(spec.inputs.size()));
  }
  const auto targets = TargetRows(spec, series);
  const auto rows = static_cast<Eigen::Index>(targets.size());
  if (rows < 1) {
    throw std::invalid_argument(
        "too few samples (" + std::to_string(series.samples()) +
        (series.breaks.empty() ? ""
                               : " in " + std::to_string(series.breaks.size() + 1) + " segments") +
        ") for the lags: need more than " + std::to_string(spec.first_target()) +
        " in one segment");
  }
  RegressionData d;
  d.x.resize(rows, spec.size());
  d.y.resize(rows, series.outputs.cols());
  Eigen::VectorXd x(spec.size());
  for (Eigen::Index r = 0; r < rows; ++r) {
    const Eigen::Index t = targets[static_cast<std::size_t>(r)];
    spec.Fill(t, series.outputs, series.inputs, x);
    d.x.row(r) = x.transpose();
    d.y.row(r) = series.outputs.row(t);
  }
  return d;
}

}  // namespace odonata::sysid
