#include "sysid/online/settling_watch.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "fuzzy/gaussian_rule_base.hpp"
#include "sysid/model/rule_listing.hpp"

namespace odonata::sysid {
namespace {

constexpr const char* kBands[3] = {"low", "medium", "high"};
/// Rules firing less than this on a sample learn nothing from it worth the update.
constexpr double kNegligibleFiring = 1e-3;

int BandOf(double scaled) { return scaled < -1.0 / 3.0 ? 0 : scaled > 1.0 / 3.0 ? 2 : 1; }

std::string Number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

/// The regressor of each signal's newest lag (RegressorSpec::RegressorNames' layout), inputs
/// first: what a pilot flies comes before what the vehicle does in response.
std::vector<int> NewestLags(const RegressorSpec& spec) {
  std::vector<int> w;
  const int no = static_cast<int>(spec.outputs.size());
  if (spec.input_lags > 0)
    for (int i = 0; i < static_cast<int>(spec.inputs.size()); ++i)
      w.push_back(no * spec.output_lags + i * spec.input_lags);
  if (spec.output_lags > 0)
    for (int o = 0; o < no; ++o) w.push_back(o * spec.output_lags);
  return w;
}

/// "high u(k)": the rule's most distinctive regressor (its centre furthest from mid-range).
std::string RegimeOf(const fuzzy::GaussianRuleBase& rb, int rule,
                     const std::vector<std::string>& names) {
  int best = 0;
  for (int i = 1; i < rb.inputs(); ++i)
    if (std::abs(rb.centre(rule, i)) > std::abs(rb.centre(rule, best))) best = i;
  const auto name = best < static_cast<int>(names.size()) ? names[static_cast<std::size_t>(best)]
                                                          : "x" + std::to_string(best + 1);
  return LinguisticLabel(rb.centre(rule, best)) + " " + name;
}

}  // namespace

const char* SettlingStateName(SettlingState s) {
  switch (s) {
    case SettlingState::kShortOfExcitation:
      return "short of excitation";
    case SettlingState::kLearning:
      return "still learning";
    case SettlingState::kSettled:
      return "settled";
  }
  return "?";
}

void SettlingWatch::Clear() { *this = SettlingWatch(); }

void SettlingWatch::Fit(const NarxModel& model) {
  // Another shape of model (other outputs or lags, without a Clear): everything starts again.
  if (outputs_.size() != static_cast<std::size_t>(model.outputs()) ||
      regressor_size_ != model.spec().size()) {
    regressor_size_ = model.spec().size();
    outputs_.assign(static_cast<std::size_t>(model.outputs()), OutputStats{});
    watched_ = NewestLags(model.spec());
    band_counts_.assign(3 * watched_.size(), 0);
    // The regimes are thirds of the range the model started with (the declared ranges online):
    // a refit rescales its model to the samples it kept, which would shrink them to what was flown.
    band_mid_.clear();
    band_half_.clear();
    for (const int w : watched_) {
      band_mid_.push_back(model.scaling().regressor_mid(w));
      band_half_.push_back(model.scaling().regressor_half(w));
    }
  }
  for (int o = 0; o < model.outputs(); ++o) {
    auto& rules = outputs_[static_cast<std::size_t>(o)].rules;
    const auto& m = model.model(o);
    const auto r = static_cast<std::size_t>(m.rules());
    // New rules are appended (the rule base grows at its end); fewer rules means one was pruned
    // and the others moved up: their statistics no longer line up, so they start again.
    if (r < rules.size()) rules.clear();
    const int p = m.consequent().LeastSquaresWidth();
    while (rules.size() < r) {
      RuleStats s;
      s.parameters = p;
      s.standard_error = std::numeric_limits<double>::infinity();
      rules.push_back(std::move(s));
    }
  }
}

void SettlingWatch::Accumulate(const NarxModel& model, const Eigen::VectorXd& regressor,
                               const Eigen::VectorXd& measured, const Eigen::VectorXd& predicted,
                               bool count_regimes) {
  const Eigen::VectorXd scaled = model.scaling().ScaleRegressor(regressor);
  if (count_regimes)
    for (std::size_t w = 0; w < watched_.size(); ++w) {
      const double scaled = (regressor(watched_[w]) - band_mid_[w]) / band_half_[w];
      ++band_counts_[3 * w + static_cast<std::size_t>(BandOf(scaled))];
    }
  for (int o = 0; o < model.outputs(); ++o) {
    const auto& m = model.model(o);
    if (m.rules() == 0) continue;
    m.rule_base().Evaluate(scaled, &inference_);
    const double e =
        model.scaling().ScaleOutput(o, measured(o)) - model.scaling().ScaleOutput(o, predicted(o));
    if (!std::isfinite(e)) continue;
    auto& rules = outputs_[static_cast<std::size_t>(o)].rules;
    for (int j = 0; j < m.rules(); ++j) {
      const double w = inference_.normalized(j);
      if (!(w >= kNegligibleFiring)) continue;
      auto& s = rules[static_cast<std::size_t>(j)];
      s.samples += w;
      s.weighted_squared_error += w * e * e;
    }
  }
}

void SettlingWatch::UpdateStandardErrors(const NarxModel& model) {
  for (int o = 0; o < model.outputs(); ++o) {
    for (auto& s : outputs_[static_cast<std::size_t>(o)].rules) {
      const double p = s.parameters;
      double se = std::numeric_limits<double>::infinity();
      if (s.samples >= kSamplesPerParameter * p)
        se = std::sqrt(s.weighted_squared_error / std::max(s.samples - p, 1.0) * p / s.samples);
      s.standard_error = se;
      if (se <= kSettledStandardError) {
        if (s.below_since < 0) s.below_since = observed_;
      } else {
        s.below_since = -1;
      }
    }
  }
}

void SettlingWatch::Observe(const NarxModel& model, const Eigen::VectorXd& regressor,
                            const Eigen::VectorXd& measured, const Eigen::VectorXd& predicted) {
  Fit(model);
  Accumulate(model, regressor, measured, predicted, true);
  ++observed_;
  if (observed_ % kCheckEvery == 0) UpdateStandardErrors(model);
}

void SettlingWatch::Rebuild(const NarxModel& model, const Series& kept) {
  for (auto& o : outputs_) o.rules.clear();
  Fit(model);
  RegressionData data;
  try {
    data = BuildRegression(model.spec(), kept);
  } catch (const std::invalid_argument&) {
    return;  // no complete regressor kept (a break every few samples): the rules start from none
  }
  for (Eigen::Index r = 0; r < data.x.rows(); ++r) {
    const Eigen::VectorXd x = data.x.row(r).transpose();
    Accumulate(model, x, data.y.row(r).transpose(), model.Predict(x), false);
  }
  UpdateStandardErrors(model);
  // The refit was fitted on these samples: a bound that holds on them has held that long.
  for (auto& o : outputs_)
    for (auto& s : o.rules)
      if (s.below_since >= 0) s.below_since = observed_ - data.x.rows();
}

const SettlingWatch::RuleStats& SettlingWatch::StatsOf(int output, int rule) const {
  // A rule the watch has seen nothing of (a model resumed frozen, never observed) has no
  // evidence: short of excitation, never settled by default.
  static const RuleStats kUnobserved = [] {
    RuleStats s;
    s.standard_error = std::numeric_limits<double>::infinity();
    return s;
  }();
  if (static_cast<std::size_t>(output) >= outputs_.size()) return kUnobserved;
  const auto& rules = outputs_[static_cast<std::size_t>(output)].rules;
  return static_cast<std::size_t>(rule) < rules.size() ? rules[static_cast<std::size_t>(rule)]
                                                       : kUnobserved;
}

SettlingState SettlingWatch::RuleState(const RuleStats& s) const {
  if (s.samples < kSamplesPerParameter * s.parameters) return SettlingState::kShortOfExcitation;
  if (s.below_since >= 0 && observed_ - s.below_since >= kSettledSamples)
    return SettlingState::kSettled;
  return SettlingState::kLearning;
}

SettlingState SettlingWatch::OutputState(int rules, bool short_of, bool learning) {
  if (rules == 0 || short_of) return SettlingState::kShortOfExcitation;
  return learning ? SettlingState::kLearning : SettlingState::kSettled;
}

std::vector<SettlingState> SettlingWatch::States(const NarxModel& model) const {
  bool regime_short = false;
  for (const int64_t n : band_counts_) regime_short |= n < kRegimeSamples;
  std::vector<SettlingState> out;
  for (int o = 0; o < model.outputs(); ++o) {
    bool short_of = regime_short, learning = false;
    const int rules = model.model(o).rules();
    for (int j = 0; j < rules; ++j) {
      const SettlingState r = RuleState(StatsOf(o, j));
      short_of |= r == SettlingState::kShortOfExcitation;
      learning |= r == SettlingState::kLearning;
    }
    out.push_back(OutputState(rules, short_of, learning));
  }
  return out;
}

std::vector<OutputSettling> SettlingWatch::Judge(const NarxModel& model) const {
  std::vector<OutputSettling> out(static_cast<std::size_t>(model.outputs()));
  const auto names = model.spec().RegressorNames();
  std::vector<RegimeSettling> regimes;
  for (std::size_t w = 0; w < watched_.size(); ++w) {
    for (int b = 0; b < 3; ++b) {
      RegimeSettling g;
      g.signal = names[static_cast<std::size_t>(watched_[w])];
      g.band = kBands[b];
      const double mid = band_mid_[w], half = band_half_[w];
      g.lower = mid + half * (-1.0 + 2.0 * b / 3.0);
      g.upper = mid + half * (-1.0 + 2.0 * (b + 1) / 3.0);
      g.samples = band_counts_[3 * w + static_cast<std::size_t>(b)];
      regimes.push_back(g);
    }
  }
  for (int o = 0; o < model.outputs(); ++o) {
    auto& judged = out[static_cast<std::size_t>(o)];
    judged.regimes = regimes;
    const auto& m = model.model(o);
    std::vector<std::string> short_of, learning;
    for (int j = 0; j < m.rules(); ++j) {
      const auto& s = StatsOf(o, j);
      RuleSettling r;
      r.samples = s.samples;
      r.standard_error = s.standard_error;
      r.regime = RegimeOf(m.rule_base(), j, names);
      const auto label = "rule " + std::to_string(j + 1) + " (" + r.regime + ")";
      r.state = RuleState(s);
      if (r.state == SettlingState::kShortOfExcitation)
        short_of.push_back(label + ": " + Number(std::floor(s.samples)) + " samples");
      else if (r.state == SettlingState::kLearning)
        learning.push_back(label + " SE " + Number(s.standard_error));
      judged.rules.push_back(r);
    }
    // Neighbouring thirds of a signal short together are one place to fly: "u(k) low to medium
    // (-1 to 0.333): 7 samples".
    for (std::size_t g = 0; g < regimes.size();) {
      if (regimes[g].samples >= kRegimeSamples) {
        ++g;
        continue;
      }
      std::size_t end = g;
      int64_t samples = regimes[g].samples;
      while (end + 1 < regimes.size() && end % 3 != 2 && regimes[end + 1].samples < kRegimeSamples)
        samples += regimes[++end].samples;
      const auto& a = regimes[g];
      const auto& b = regimes[end];
      short_of.push_back(a.signal + " " + a.band + (end > g ? " to " + b.band : "") + " (" +
                         Number(a.lower) + " to " + Number(b.upper) +
                         "): " + std::to_string(samples) + " samples");
      g = end + 1;
    }
    const auto list = [](const std::vector<std::string>& items) {
      std::string s;
      const std::size_t shown = std::min<std::size_t>(items.size(), 3);
      for (std::size_t i = 0; i < shown; ++i) s += (i ? "; " : "") + items[i];
      if (items.size() > shown) s += "; " + std::to_string(items.size() - shown) + " more";
      return s;
    };
    judged.state = OutputState(m.rules(), !short_of.empty(), !learning.empty());
    if (judged.state == SettlingState::kShortOfExcitation) {
      judged.sentence = m.rules() == 0
                            ? "short of excitation: no rule yet"
                            : "short of excitation: " + list(short_of) + ", fly more there";
    } else if (judged.state == SettlingState::kLearning) {
      judged.sentence = "still learning: " + list(learning) + " (settled at " +
                        Number(kSettledStandardError) + ")";
    } else {
      judged.sentence = "settled";
    }
  }
  return out;
}

}  // namespace odonata::sysid
