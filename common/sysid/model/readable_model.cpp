#include "sysid/model/readable_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>

#include "fuzzy/fuzzy_model_state.hpp"
#include "fuzzy/linear_consequent.hpp"
#include "fuzzy/singleton_consequent.hpp"
#include "sysid/model/local_dynamics.hpp"
#include "sysid/model/narx_model_state.hpp"
#include "sysid/model/rule_listing.hpp"

namespace odonata::sysid {
namespace {

// A premise wider than this (scaled) is flat over the range: the rule leaves the signal out.
constexpr double kFlat = 10.0;
// What a signal left out of a rule holds: a Gaussian this wide is flat over the range.
constexpr double kLeftOut = 1000.0;
const char* const kTermNames[kReadableTerms] = {"very low", "low", "medium", "high", "very high"};

// A signal of the regressor (an output or an input) and its columns, one per lag.
struct Signal {
  std::string name;
  std::vector<Eigen::Index> columns;
};

std::vector<Signal> Signals(const RegressorSpec& spec) {
  std::vector<Signal> s;
  Eigen::Index c = 0;
  for (const auto& o : spec.outputs) {
    Signal sig{o, {}};
    for (int l = 0; l < spec.output_lags; ++l) sig.columns.push_back(c++);
    if (!sig.columns.empty()) s.push_back(sig);
  }
  for (const auto& i : spec.inputs) {
    Signal sig{i, {}};
    for (int l = 0; l < spec.input_lags; ++l) sig.columns.push_back(c++);
    if (!sig.columns.empty()) s.push_back(sig);
  }
  return s;
}

// A rule's scaled consequent: [a0; a_1 … a_N] (a singleton: its centre, then zeros).
Eigen::VectorXd Theta(const fuzzy::FuzzyModel& fm, int rule) {
  if (fm.consequent().kind() == fuzzy::ConsequentKind::kSingleton) {
    Eigen::VectorXd t = Eigen::VectorXd::Zero(fm.inputs() + 1);
    t(0) = static_cast<const fuzzy::SingletonConsequent&>(fm.consequent()).centre(rule);
    return t;
  }
  return static_cast<const fuzzy::LinearConsequent&>(fm.consequent()).coefficients(rule);
}

// A signal's shared terms, and which one each full rule's premise maps onto (−1: it leaves the
// signal out).
struct Terms {
  std::vector<double> centre, sigma;  // scaled
  std::vector<std::string> name;
  std::vector<int> of_rule;
};

// Premises whose centres lie within kSameCentre of a cluster's first are one term; beyond five
// terms the nearest neighbours merge. Each term sits at its members' mean centre with their mean
// width, so a rule keeps its own premise unless five terms cannot hold them all. Names go by
// rank: two terms are low and high, three add medium, four are very low, low, high, very high.
constexpr double kSameCentre = 0.05;  // scaled: 2.5 % of the signal's range
Terms ClusterTerms(const std::vector<double>& centres, const std::vector<double>& widths,
                   const std::vector<bool>& flat, double sigma_min) {
  std::vector<std::size_t> order;
  for (std::size_t j = 0; j < centres.size(); ++j)
    if (!flat[j]) order.push_back(j);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return centres[a] < centres[b]; });
  std::vector<std::vector<std::size_t>> clusters;
  for (const auto j : order) {
    if (clusters.empty() || centres[j] - centres[clusters.back().front()] > kSameCentre)
      clusters.push_back({});
    clusters.back().push_back(j);
  }
  const auto mean = [&](const std::vector<std::size_t>& c, const std::vector<double>& v) {
    double s = 0;
    for (const auto j : c) s += v[j];
    return s / static_cast<double>(c.size());
  };
  while (clusters.size() > static_cast<std::size_t>(kReadableTerms)) {
    std::size_t best = 0;
    for (std::size_t i = 1; i + 1 < clusters.size(); ++i)
      if (mean(clusters[i + 1], centres) - mean(clusters[i], centres) <
          mean(clusters[best + 1], centres) - mean(clusters[best], centres))
        best = i;
    clusters[best].insert(clusters[best].end(), clusters[best + 1].begin(),
                          clusters[best + 1].end());
    clusters.erase(clusters.begin() + static_cast<std::ptrdiff_t>(best) + 1);
  }
  static const std::vector<std::vector<int>> kByCount = {{},        {2},          {1, 3},
                                                         {1, 2, 3}, {0, 1, 3, 4}, {0, 1, 2, 3, 4}};
  Terms t;
  t.of_rule.assign(centres.size(), -1);
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    t.centre.push_back(mean(clusters[k], centres));
    t.sigma.push_back(std::max(mean(clusters[k], widths), sigma_min));
    t.name.push_back(kTermNames[kByCount[clusters.size()][k]]);
    for (const auto j : clusters[k]) t.of_rule[j] = static_cast<int>(k);
  }
  return t;
}

// Merged readable rules: for each, the term of every signal (−1: left out) → the full rules it
// stands for.
using MergedRules = std::map<std::vector<int>, std::vector<int>>;

// One output's way from its full rules to readable ones: each signal's terms, the full rules
// grouped by the terms they fall in, and the readable rules built from a choice of the signals
// shown.
class OutputReduction {
 public:
  OutputReduction(const fuzzy::FuzzyModel& fm, const fuzzy::FuzzyModelState& f,
                  const std::vector<Signal>& signals, double coincide)
      : fm_(fm),
        signals_(signals),
        clock_(f.clock),
        kind_(f.consequent.kind),
        initial_covariance_(f.consequent.initial_covariance) {
    const int r = fm.rules();
    // All local models the same: the premises change nothing, the model is linear.
    for (int j = 1; j < r && linear_; ++j)
      linear_ = (Theta(fm, j) - Theta(fm, 0)).cwiseAbs().sum() <= coincide;
    std::vector<std::vector<int>> term_of_rule(static_cast<std::size_t>(r));
    for (const auto& sig : signals) {
      Terms t = TermsOf(sig, f.config.entropy.sigma_min);
      for (int j = 0; j < r; ++j)
        term_of_rule[static_cast<std::size_t>(j)].push_back(
            linear_ ? -1 : t.of_rule[static_cast<std::size_t>(j)]);
      terms_.push_back(std::move(t));
    }
    for (int j = 0; j < r; ++j) groups_[term_of_rule[static_cast<std::size_t>(j)]].push_back(j);
  }

  bool linear() const { return linear_; }
  const std::vector<Terms>& terms() const { return terms_; }

  // A signal whose term is the same in every readable rule tells none of them apart.
  std::vector<bool> Telling() const {
    std::vector<bool> kept(signals_.size(), false);
    for (std::size_t s = 0; s < signals_.size(); ++s)
      for (const auto& [key, rules] : groups_)
        if (key[s] != groups_.begin()->first[s]) kept[s] = true;
    return kept;
  }

  // The readable rules showing the signals `keep` marks: full rules whose shown terms agree
  // merge.
  MergedRules Merge(const std::vector<bool>& keep) const {
    MergedRules merged;
    for (const auto& [key, members] : groups_) {
      std::vector<int> shown(key.size(), -1);
      for (std::size_t s = 0; s < key.size(); ++s)
        if (keep[s]) shown[s] = key[s];
      auto& all = merged[shown];
      all.insert(all.end(), members.begin(), members.end());
    }
    return merged;
  }

  // The output's readable rules from `merged` into `into` (its rules, consequents, covariances)
  // and their terms into `shown_terms`. Per readable rule, its full rules' consequents and rule
  // weights (output widths) are averaged, so a rule that stands alone keeps its own exactly.
  void Build(const MergedRules& merged, fuzzy::FuzzyModelState* into,
             std::vector<std::vector<int>>* shown_terms) const {
    const auto& rb = fm_.rule_base();
    std::vector<fuzzy::RuleState> rules;
    std::vector<std::vector<double>> coefficients, covariances;
    shown_terms->clear();
    for (const auto& [shown, members] : merged) {
      Eigen::VectorXd theta = Eigen::VectorXd::Zero(fm_.inputs() + 1);
      double width = 0;
      for (const int j : members) {
        theta += Theta(fm_, j) / static_cast<double>(members.size());
        width += rb.output_width(j) / static_cast<double>(members.size());
      }
      fuzzy::RuleState rule;
      rule.centre.assign(static_cast<std::size_t>(fm_.inputs()), 0.0);
      rule.sigma.assign(static_cast<std::size_t>(fm_.inputs()), kLeftOut);
      for (std::size_t s = 0; s < signals_.size(); ++s)
        if (shown[s] >= 0)
          for (const auto c : signals_[s].columns) {
            const auto& term = terms_[s];
            rule.centre[static_cast<std::size_t>(c)] =
                term.centre[static_cast<std::size_t>(shown[s])];
            rule.sigma[static_cast<std::size_t>(c)] =
                term.sigma[static_cast<std::size_t>(shown[s])];
          }
      rule.output_width = width;
      rule.born = clock_;
      rules.push_back(rule);
      if (kind_ == fuzzy::ConsequentKind::kSingleton) {
        coefficients.push_back({theta(0)});
      } else {
        coefficients.emplace_back(theta.data(), theta.data() + theta.size());
        const auto n1 = static_cast<std::size_t>(theta.size());
        std::vector<double> p(n1 * n1, 0.0);
        for (std::size_t k = 0; k < n1; ++k) p[k * n1 + k] = initial_covariance_;
        covariances.push_back(std::move(p));
      }
      shown_terms->push_back(shown);
    }
    into->rules = rules;
    into->consequent.coefficients = coefficients;
    into->consequent.covariances = covariances;
  }

 private:
  // A signal's terms: the rules' premises on it (averaged over its lags) clustered into at
  // most five, named in order (ReadableTerms), each at its members' mean centre and width.
  Terms TermsOf(const Signal& sig, double sigma_min) const {
    const auto& rb = fm_.rule_base();
    const int r = fm_.rules();
    std::vector<double> centres(static_cast<std::size_t>(r)), widths(static_cast<std::size_t>(r));
    std::vector<bool> flat(static_cast<std::size_t>(r), true);
    for (int j = 0; j < r; ++j) {
      double c = 0, w = 0;
      int n = 0;
      for (const auto col : sig.columns)
        if (rb.sigma(j, static_cast<int>(col)) <= kFlat) {
          c += rb.centre(j, static_cast<int>(col));
          w += rb.sigma(j, static_cast<int>(col));
          ++n;
        }
      const auto k = static_cast<std::size_t>(j);
      if (n > 0) {
        centres[k] = c / n;
        widths[k] = w / n;
        flat[k] = false;
      }
    }
    return ClusterTerms(centres, widths, flat, sigma_min);
  }

  const fuzzy::FuzzyModel& fm_;
  const std::vector<Signal>& signals_;
  int64_t clock_;
  fuzzy::ConsequentKind kind_;
  double initial_covariance_;
  bool linear_ = true;
  std::vector<Terms> terms_;
  MergedRules groups_;  // signals' terms → full rules
};

// The training score in the full model's mode: K steps ahead, else free run (one step without
// output lags).
double TrainingScore(const NarxModel& m, const Series& train, const ReadableOptions& options) {
  return options.criterion_horizon > 1 ? m.NdeiAhead(train, options.criterion_horizon)
                                       : m.Ndei(train, m.spec().output_lags > 0);
}

// More rules than a person takes in at once: the signal whose terms cost least to leave out of
// every rule (the training score, with consequents fitted again) goes, until at most
// options.max_rules remain; the cost shows in the readable form's FIT. Returns the signals kept.
std::vector<bool> SignalsShown(const OutputReduction& reduction, const NarxModelState& state, int o,
                               const Eigen::MatrixXd& xs, const Eigen::MatrixXd& ys,
                               const Series& train, const ReadableOptions& options) {
  std::vector<bool> kept = reduction.Telling();
  const std::size_t n = kept.size();
  while (reduction.Merge(kept).size() > static_cast<std::size_t>(options.max_rules)) {
    double best = std::numeric_limits<double>::infinity();
    std::size_t drop = n;
    for (std::size_t s = 0; s < n; ++s) {
      if (!kept[s]) continue;
      std::vector<bool> trial = kept;
      trial[s] = false;
      NarxModelState candidate = state;
      std::vector<std::vector<int>> unused;
      reduction.Build(reduction.Merge(trial), &candidate.models[static_cast<std::size_t>(o)],
                      &unused);
      NarxModel m = NarxModel::FromState(candidate);
      m.mutable_model(o).RefineConsequents(xs, ys.col(o));
      const double score = TrainingScore(m, train, options);
      if (drop == n || score < best) {
        best = score;
        drop = s;
      }
    }
    if (drop == n) break;
    kept[drop] = false;
  }
  return kept;
}

// Output o's rules as sentences, then the terms they use in raw units (a signal's lags share
// its range).
std::vector<std::string> Sentences(const NarxModel& readable, int o,
                                   const std::vector<Signal>& signals,
                                   const std::vector<std::vector<int>>& rule_terms,
                                   const std::vector<Terms>& term_sets, double sample_time_s) {
  const RegressorSpec& spec = readable.spec();
  std::vector<std::string> lines;
  const std::string target = spec.TargetName(o);
  for (std::size_t j = 0; j < rule_terms.size(); ++j) {
    const RawLinearModel raw = RuleLinearModel(readable, o, static_cast<int>(j));
    std::string s;
    for (std::size_t k = 0; k < signals.size(); ++k)
      if (rule_terms[j][k] >= 0)
        s += (s.empty() ? "IF " : " AND ") + signals[k].name + " is " +
             term_sets[k].name[static_cast<std::size_t>(rule_terms[j][k])];
    const std::string then =
        readable.model(o).consequent().kind() == fuzzy::ConsequentKind::kSingleton
            ? target + " is ≈" + SentenceNumber(raw.constant)
            : target + " ≈ " + DescribeLinearModel(spec, o, raw, sample_time_s);
    lines.push_back(s.empty() ? (rule_terms.size() == 1 ? "linear: one rule: " : "") + then
                              : s + " THEN " + then);
  }
  const Scaling& sc = readable.scaling();
  for (std::size_t k = 0; k < signals.size(); ++k) {
    std::vector<int> used;
    for (const auto& t : rule_terms)
      if (t[k] >= 0 && std::find(used.begin(), used.end(), t[k]) == used.end())
        used.push_back(t[k]);
    if (used.empty()) continue;
    std::sort(used.begin(), used.end());
    const auto c = static_cast<int>(signals[k].columns.front());
    const Terms& ts = term_sets[k];
    std::string line = signals[k].name + ":";
    for (const int t : used) {
      const auto u = static_cast<std::size_t>(t);
      line += std::string(t == used.front() ? " " : ", ") + ts.name[u] + " ≈ " +
              SentenceNumber(sc.regressor_mid(c) + sc.regressor_half(c) * ts.centre[u]) + " ±" +
              SentenceNumber(sc.regressor_half(c) * ts.sigma[u]);
    }
    lines.push_back(line);
  }
  return lines;
}

}  // namespace

ReadableModel MakeReadable(const NarxModel& full, const Series& train, double sample_time_s,
                           const ReadableOptions& options) {
  const RegressorSpec& spec = full.spec();
  const RegressionData d = BuildRegression(spec, train);
  if (d.x.rows() == 0) throw std::invalid_argument("readable model: no training rows");
  const Eigen::MatrixXd xs = full.scaling().ScaleRegressorRows(d.x);
  const Eigen::MatrixXd ys = full.scaling().ScaleOutputRows(d.y);
  const std::vector<Signal> signals = Signals(spec);
  NarxModelState state = full.State();
  state.envelope = DataEnvelope{};  // fitted again below, around the readable rules
  const auto outputs = static_cast<std::size_t>(full.outputs());
  std::vector<bool> linear(outputs, false);
  // Per output and readable rule, the term of each signal (−1: left out).
  std::vector<std::vector<std::vector<int>>> terms(outputs);
  std::vector<std::vector<Terms>> term_sets(outputs);
  for (int o = 0; o < full.outputs(); ++o) {
    const auto k = static_cast<std::size_t>(o);
    fuzzy::FuzzyModelState& f = state.models[k];
    const OutputReduction reduction(full.model(o), f, signals, options.coincide);
    const std::vector<bool> kept = SignalsShown(reduction, state, o, xs, ys, train, options);
    reduction.Build(reduction.Merge(kept), &f, &terms[k]);
    term_sets[k] = reduction.terms();
    linear[k] = reduction.linear();
  }
  NarxModel readable = NarxModel::FromState(state);
  // The premises are the shared terms now. The rules' own consequents (averaged where rules
  // merged) keep what the full model's training chose them for (a K-step or free-run criterion);
  // consequents fitted again by least squares suit the new premises better one step ahead. The
  // one that scores better on the training data, in the mode the full model was chosen by, stays
  // (a linear model keeps its own: it is the full model's exactly).
  bool all_linear = true;
  for (const bool l : linear) all_linear = all_linear && l;
  if (!all_linear) {
    NarxModel refit = readable;
    for (int o = 0; o < refit.outputs(); ++o)
      refit.mutable_model(o).RefineConsequents(xs, ys.col(o));
    const double own = TrainingScore(readable, train, options);
    const double fitted = TrainingScore(refit, train, options);
    if (std::isfinite(fitted) && !(fitted >= own)) readable = refit;
  }
  if (full.envelope().any()) {
    state = readable.State();
    std::vector<fuzzy::FuzzyModel> models;
    for (int o = 0; o < readable.outputs(); ++o) models.push_back(readable.model(o));
    state.envelope = DataEnvelope::Fit(models, xs, ys);
    readable = NarxModel::FromState(state);
  }
  ReadableModel out{readable, {}, linear};
  for (int o = 0; o < readable.outputs(); ++o) {
    const auto k = static_cast<std::size_t>(o);
    out.sentences.push_back(Sentences(readable, o, signals, terms[k], term_sets[k], sample_time_s));
  }
  return out;
}

}  // namespace odonata::sysid
