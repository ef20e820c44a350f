#include "sysid/model/excitation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "sysid/model/nothing_to_identify.hpp"

namespace odonata::sysid {
namespace {

SignalExcitation Describe(const std::string& name, bool output,
                          const Eigen::Ref<const Eigen::VectorXd>& v) {
  SignalExcitation e;
  e.name = name;
  e.output = output;
  if (v.size() == 0) return e;
  e.min = v.minCoeff();
  e.max = v.maxCoeff();
  const double mean = v.mean();
  e.std = std::sqrt((v.array() - mean).square().mean());
  std::set<double> levels;
  for (Eigen::Index i = 0; i < v.size() && levels.size() < 1000; ++i) levels.insert(v(i));
  e.levels = static_cast<long>(levels.size());
  e.constant = e.max - e.min <= 1e-9 * std::max(std::abs(e.max), std::abs(e.min));
  return e;
}

std::string Number(double x) {
  char s[32];
  std::snprintf(s, sizeof s, "%.6g", x);
  return s;
}

}  // namespace

ExcitationReport CheckExcitation(const RegressorSpec& spec, const Series& train,
                                 const ExcitationNeeds& needs, const std::string& source) {
  ExcitationReport r;
  for (std::size_t k = 0; k < spec.outputs.size(); ++k)
    r.signals.push_back(Describe(spec.outputs[k], true, train.outputs.col(Eigen::Index(k))));
  for (std::size_t k = 0; k < spec.inputs.size(); ++k)
    r.signals.push_back(Describe(spec.inputs[k], false, train.inputs.col(Eigen::Index(k))));
  for (const SignalExcitation& e : r.signals) {
    if (e.constant && e.output)
      throw NothingToIdentify(source + ": the output '" + e.name + "' never moves (" +
                              Number(e.min) +
                              " throughout): there is nothing to identify; "
                              "record a part of the flight where it moves (--from/--to, "
                              "--airborne)");
    if (e.constant && spec.input_lags > 0)
      throw NothingToIdentify(source + ": the input '" + e.name + "' never moves (" +
                              Number(e.min) +
                              " throughout): its effect cannot be identified; "
                              "excite it (a manoeuvre that moves it), keep only the part where "
                              "it moves (--from/--to, --airborne), or leave it out");
    if (e.output && e.levels <= 5)
      r.warnings.push_back(source + ": the output '" + e.name + "' takes only " +
                           std::to_string(e.levels) +
                           " distinct values: quantised this coarsely, it limits any model");
  }
  r.targets = static_cast<long>(TargetRows(spec, train).size());
  const long regressors = spec.size() + 1;
  const long needed = 2 * regressors + std::max(needs.horizon, 0);
  if (r.targets < needed)
    throw NothingToIdentify(
        source + ": " + std::to_string(train.samples()) + " samples give " +
        std::to_string(r.targets) + " targets, fewer than the " + std::to_string(needed) +
        " that " + std::to_string(regressors) + " regressors" +
        (needs.horizon > 0 ? " and a " + std::to_string(needs.horizon) + "-step horizon"
                           : std::string()) +
        " need: give a longer record, or fewer lags");
  r.holdout_targets = needs.holdout_targets >= 0
                          ? needs.holdout_targets
                          : static_cast<long>(std::floor(needs.holdout_fraction * r.targets));
  const long holdout_needed = std::max<long>(20, 3 * regressors);
  if ((needs.holdout_fraction > 0 || needs.holdout_targets >= 0) &&
      r.holdout_targets < holdout_needed)
    throw NothingToIdentify(
        source + ": settings would be chosen on " + std::to_string(r.holdout_targets) +
        " samples, fewer than the " + std::to_string(holdout_needed) + " that " +
        std::to_string(regressors) +
        " regressors need for a choice to mean anything: give a longer record, a selection "
        "file (--select), or fix the settings (--no-select)");
  return r;
}

}  // namespace odonata::sysid
