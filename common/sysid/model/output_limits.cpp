#include "sysid/model/output_limits.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "io/json_number.hpp"

namespace odonata::sysid {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// True when `value` is held for kMinRun samples in a row and on kMinShare of them.
bool Saturated(const Eigen::Ref<const Eigen::VectorXd>& y, double value) {
  Eigen::Index run = 0, longest = 0, count = 0;
  for (Eigen::Index r = 0; r < y.size(); ++r) {
    if (y(r) == value) {
      ++count;
      longest = std::max(longest, ++run);
    } else {
      run = 0;
    }
  }
  return longest >= OutputLimits::kMinRun &&
         double(count) >= OutputLimits::kMinShare * double(y.size());
}

}  // namespace

OutputLimits OutputLimits::Detect(const Eigen::Ref<const Eigen::MatrixXd>& outputs) {
  OutputLimits l;
  l.lower = Eigen::VectorXd::Constant(outputs.cols(), -kInf);
  l.upper = Eigen::VectorXd::Constant(outputs.cols(), kInf);
  for (Eigen::Index o = 0; o < outputs.cols(); ++o) {
    const Eigen::VectorXd y = outputs.col(o);
    double lo = kInf, hi = -kInf;
    for (Eigen::Index r = 0; r < y.size(); ++r) {
      if (!std::isfinite(y(r))) continue;
      lo = std::min(lo, y(r));
      hi = std::max(hi, y(r));
    }
    if (!(lo < hi)) continue;  // constant or empty: nothing to hold
    if (Saturated(y, hi)) l.upper(o) = hi;
    if (Saturated(y, lo)) l.lower(o) = lo;
  }
  if (!l.any()) return {};
  return l;
}

bool OutputLimits::any() const {
  for (Eigen::Index o = 0; o < lower.size(); ++o)
    if (std::isfinite(lower(o)) || std::isfinite(upper(o))) return true;
  return false;
}

std::string OutputLimits::Problems(int outputs) const {
  if (lower.size() == 0 && upper.size() == 0) return {};
  if (lower.size() != outputs || upper.size() != outputs)
    return "output limits: " + std::to_string(lower.size()) + " lower and " +
           std::to_string(upper.size()) + " upper for " + std::to_string(outputs) + " outputs";
  for (int o = 0; o < outputs; ++o) {
    if (std::isnan(lower(o)) || std::isnan(upper(o)))
      return "output limits: output " + std::to_string(o) + " has a NaN limit";
    if (!(lower(o) < upper(o)))
      return "output limits: output " + std::to_string(o) + "'s lower limit is not below its upper";
  }
  return {};
}

nlohmann::json OutputLimits::ToJson() const {
  nlohmann::json lo = nlohmann::json::array(), hi = nlohmann::json::array();
  for (Eigen::Index o = 0; o < lower.size(); ++o) {
    lo.push_back(io::FiniteOrNull(lower(o)));
    hi.push_back(io::FiniteOrNull(upper(o)));
  }
  return {{"lower", lo}, {"upper", hi}};
}

OutputLimits OutputLimits::FromJson(const nlohmann::json& j, int outputs) {
  OutputLimits l;
  const auto& lo = j.at("lower");
  const auto& hi = j.at("upper");
  if (!lo.is_array() || !hi.is_array() || lo.size() != static_cast<std::size_t>(outputs) ||
      hi.size() != static_cast<std::size_t>(outputs))
    throw std::runtime_error("output_limits: need lower and upper arrays of " +
                             std::to_string(outputs) + " (null for none)");
  l.lower.resize(outputs);
  l.upper.resize(outputs);
  for (int o = 0; o < outputs; ++o) {
    const auto k = static_cast<std::size_t>(o);
    l.lower(o) = lo[k].is_null() ? -kInf : lo[k].get<double>();
    l.upper(o) = hi[k].is_null() ? kInf : hi[k].get<double>();
  }
  const std::string p = l.Problems(outputs);
  if (!p.empty()) throw std::runtime_error(p);
  if (!l.any()) return {};
  return l;
}

}  // namespace odonata::sysid
