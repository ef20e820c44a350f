#include "sysid/model/signal_ranges.hpp"

#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace odonata::sysid {
namespace {
std::pair<double, double> RangeOf(const SignalRanges& ranges, const std::string& name) {
  const auto it = ranges.find(name);
  if (it == ranges.end()) throw std::runtime_error("no range declared for signal '" + name + "'");
  const auto [lo, hi] = it->second;
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo)) {
    throw std::runtime_error("range of '" + name + "' must be finite with max > min");
  }
  return it->second;
}
}  // namespace

Scaling ScalingFromRanges(const RegressorSpec& spec, const SignalRanges& ranges) {
  Scaling s;
  s.regressor_mid.resize(spec.size());
  s.regressor_half.resize(spec.size());
  Eigen::Index c = 0;
  auto fill = [&](const std::string& name, int lags) {
    const auto [lo, hi] = RangeOf(ranges, name);
    for (int l = 0; l < lags; ++l, ++c) {
      s.regressor_mid(c) = 0.5 * (hi + lo);
      s.regressor_half(c) = 0.5 * (hi - lo);
    }
  };
  for (const auto& o : spec.outputs) fill(o, spec.output_lags);
  for (const auto& u : spec.inputs) fill(u, spec.input_lags);
  const auto n = static_cast<Eigen::Index>(spec.outputs.size());
  s.output_mean.resize(n);
  s.output_std.resize(n);
  for (Eigen::Index o = 0; o < n; ++o) {
    const auto [lo, hi] = RangeOf(ranges, spec.outputs[static_cast<std::size_t>(o)]);
    s.output_mean(o) = 0.5 * (hi + lo);
    s.output_std(o) = 0.5 * (hi - lo);
  }
  return s;
}

SignalRanges RangesFromSeries(const RegressorSpec& spec, const Series& series) {
  SignalRanges r;
  auto add = [&r](const std::string& name, const Eigen::VectorXd& v) {
    double lo = v.minCoeff(), hi = v.maxCoeff();
    if (!(hi > lo)) {  // a constant signal still needs a non-empty range
      lo -= 1.0;
      hi += 1.0;
    }
    r[name] = {lo, hi};
  };
  for (std::size_t o = 0; o < spec.outputs.size(); ++o)
    add(spec.outputs[o], series.outputs.col(static_cast<Eigen::Index>(o)));
  for (std::size_t i = 0; i < spec.inputs.size(); ++i)
    add(spec.inputs[i], series.inputs.col(static_cast<Eigen::Index>(i)));
  return r;
}

nlohmann::json RangesToJson(const SignalRanges& ranges) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, r] : ranges) j[name] = {r.first, r.second};
  return j;
}

SignalRanges RangesFromJson(const nlohmann::json& j) {
  if (!j.is_object()) throw std::runtime_error("ranges must be an object {\"signal\": [min, max]}");
  SignalRanges r;
  for (const auto& [name, v] : j.items()) {
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number()) {
      throw std::runtime_error("range of '" + name + "' must be [min, max]");
    }
    r[name] = {v[0].get<double>(), v[1].get<double>()};
  }
  return r;
}

}  // namespace odonata::sysid
