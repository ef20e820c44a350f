// Whether the fuzzy model earns its place beside the linear one: its rest behaviour, the margin it
// must beat the linear model by, the paired standard error of fold scores, and the blocked
// cross-validation of the chosen setting against the linear model.

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>

#include "sysid/model/free_run.hpp"
#include "sysid/selection/model_selection.hpp"
#include "sysid/selection/parallel_for.hpp"
#include "sysid/selection/selection_steps.hpp"

namespace odonata::sysid {

double RestDeviation(const NarxModel& model, const Series& train) {
  const RegressorSpec& spec = model.spec();
  const Eigen::Index n = std::clamp<Eigen::Index>(train.samples(), 1000, 10000);
  Series rest;
  rest.inputs = train.inputs.colwise().mean().replicate(n, 1);
  const Eigen::RowVectorXd mean = train.outputs.colwise().mean();
  const Eigen::RowVectorXd sd =
      ((train.outputs.rowwise() - mean).array().square().colwise().mean()).sqrt().matrix();
  rest.outputs = (mean + 0.1 * sd).replicate(n, 1);
  const Predictor predict = [&model](const Eigen::VectorXd& x) { return model.Predict(x); };
  bool diverged = false;
  const Eigen::MatrixXd run = SimulateFreeRun(spec, rest, predict, &diverged);
  if (diverged || !run.allFinite()) return std::numeric_limits<double>::infinity();
  const Eigen::Index tail = run.rows() / 4;
  double sum = 0.0;
  for (Eigen::Index o = 0; o < run.cols(); ++o) {
    const Eigen::VectorXd last = run.col(o).tail(tail);
    const double spread = std::sqrt((last.array() - last.mean()).square().mean());
    sum += spread / std::max(sd(o), 1e-300);
  }
  const double d = sum / double(run.cols());
  return std::isfinite(d) ? d : std::numeric_limits<double>::infinity();
}

namespace {

// Held at rest, a run whose last quarter still moves by more than this share of the outputs'
// deviation has not settled.
constexpr double kRestTolerance = 0.01;

}  // namespace

bool Restless(double rest_deviation, double linear_rest) {
  return !(rest_deviation <= std::max(kRestTolerance, 10.0 * linear_rest));
}

bool BeatsByMargin(double challenger, double incumbent, const SelectionOptions& options) {
  return challenger < std::min(incumbent / (1.0 + options.relative_tolerance),
                               incumbent - options.absolute_tolerance);
}

const char* LinearFitName(const SelectionResult& result) {
  return result.output_error_linear ? "its output-error fit" : "ARX";
}

bool SamePremises(const NarxModel& a, const NarxModel& b) {
  if (a.outputs() != b.outputs()) return false;
  for (int o = 0; o < a.outputs(); ++o) {
    const fuzzy::GaussianRuleBase& p = a.model(o).rule_base();
    const fuzzy::GaussianRuleBase& q = b.model(o).rule_base();
    if (p.inputs() != q.inputs() || p.rules() != q.rules()) return false;
    if ((p.output_widths() != q.output_widths()).any()) return false;
    for (int i = 0; i < p.inputs(); ++i)
      if ((p.centres_of_input(i) != q.centres_of_input(i)).any() ||
          (p.sigmas_of_input(i) != q.sigmas_of_input(i)).any())
        return false;
  }
  return true;
}

double PairedStandardError(const std::vector<double>& a, const std::vector<double>& b) {
  const std::size_t k = a.size();
  if (k < 2 || b.size() != k) return 0.0;
  double sum = 0, sum_sq = 0;
  for (std::size_t f = 0; f < k; ++f) {
    const double d = b[f] - a[f];
    if (!std::isfinite(d)) return 0.0;
    sum += d;
    sum_sq += d * d;
  }
  const double n = static_cast<double>(k);
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, (sum_sq - n * mean * mean) / (n - 1)) / n);
}

// Blocked cross-validation of the chosen fuzzy setting against the linear model: fold k is
// scored after training on the rest of `train`, the seam a break.
// `linear_folds`, when given, are the linear model's fold scores from an earlier check.
// `second_look`: the fuzzy candidate is not the hold-out's choice, so the folds alone must show
// that it beats the linear model (below).
LinearCheck CrossValidate(const SelectionContext& ctx, const Candidate& fuzzy_c,
                          const Candidate& linear_c, const std::vector<double>* linear_folds,
                          bool second_look) {
  const Series& train = ctx.train;
  const SelectionOptions& options = ctx.options;
  const RegressorSpec& spec = ctx.spec;
  LinearCheck check;
  const Eigen::Index n = train.samples();
  const int k = options.linear_check_folds;
  const Eigen::Index need = spec.first_target() + 2;
  if (n / k < need || n - n / k < need) return check;
  // Each fold and each setting trains alone: 2k independent trainings, in parallel.
  std::vector<Series> folds, rests;
  for (int f = 0; f < k; ++f) {
    const Eigen::Index begin = n * f / k, end = n * (f + 1) / k;
    folds.push_back(SliceSeries(train, begin, end - begin));
    rests.push_back(ConcatSeries(SliceSeries(train, 0, begin), SliceSeries(train, end, n - end)));
    if (TargetRows(spec, folds.back()).size() < 2 || TargetRows(spec, rests.back()).size() < 2)
      return check;
  }
  const bool linear_known =
      linear_folds != nullptr && linear_folds->size() == static_cast<std::size_t>(k);
  const std::size_t per_fold = linear_known ? 1 : 2;
  std::vector<double> scores(per_fold * static_cast<std::size_t>(k));
  ParallelFor(scores.size(), ResolveThreads(options.threads), [&](std::size_t i) {
    const std::size_t f = i / per_fold;
    const bool fuzzy = i % per_fold == 0;
    const Candidate& c = fuzzy ? fuzzy_c : linear_c;
    const NarxModel m =
        TrainCandidate(ctx, c, rests[f], nullptr, fuzzy ? std::max(1, c.epochs) : 1, nullptr, true);
    scores[i] = Score(m, folds[f], ctx.horizon);
  });
  for (int f = 0; f < k; ++f) {
    check.fuzzy_folds.push_back(scores[per_fold * static_cast<std::size_t>(f)]);
    check.linear_folds.push_back(linear_known ? (*linear_folds)[static_cast<std::size_t>(f)]
                                              : scores[per_fold * static_cast<std::size_t>(f) + 1]);
  }
  auto mean = [](const std::vector<double>& v) {
    double sum = 0;
    for (const double x : v) sum += x;
    return sum / double(v.size());
  };
  check.done = true;
  check.fuzzy_score = mean(check.fuzzy_folds);
  check.linear_score = mean(check.linear_folds);
  // As in the choice among candidates: a difference below the absolute tolerance (half a FIT
  // point) does not pay for the rules. For a second look, nor does one below its own standard
  // error over the folds (the one-standard-error rule, paired since both settings see the same
  // folds): the hold-out preferred another candidate, and each further look is one more chance
  // for a lucky fold to decide a mean of a few short folds (docs/identifier.md §9).
  check.margin = options.absolute_tolerance;
  if (second_look)
    check.margin =
        std::max(check.margin, PairedStandardError(check.fuzzy_folds, check.linear_folds));
  check.linear_chosen = !(check.fuzzy_score + check.margin < check.linear_score);
  return check;
}

void CheckAgainstLinear(const SelectionContext& ctx, SelectionState& st) {
  SelectionResult& result = st.result;
  const auto& cs = result.candidates;
  const std::size_t linear = *st.linear_index;
  // The chosen candidate first, then the others by hold-out score, until one beats ARX.
  std::vector<std::size_t> order{result.chosen};
  for (std::size_t k = 0; k < cs.size(); ++k)
    if (k != result.chosen && k != linear && std::isfinite(cs[k].score)) order.push_back(k);
  std::stable_sort(order.begin() + 1, order.end(),
                   [&](std::size_t a, std::size_t b) { return cs[a].score < cs[b].score; });
  order.resize(std::min(
      order.size(), static_cast<std::size_t>(std::max(1, ctx.options.linear_check_candidates))));
  std::optional<std::size_t> winner;
  for (const std::size_t k : order) {
    LinearCheck check =
        CrossValidate(ctx, cs[k], cs[linear], st.linear_folds.empty() ? nullptr : &st.linear_folds,
                      k != result.chosen);
    if (check.done) st.linear_folds = check.linear_folds;
    if (!check.done) break;  // too short to fold: the hold-out alone decides
    check.candidate = k;
    result.linear_checks.push_back(check);
    if (!check.linear_chosen) {
      winner = k;
      break;
    }
  }
  if (result.linear_checks.empty()) return;
  const LinearCheck& first = result.linear_checks.front();
  result.linear_check = winner ? result.linear_checks.back() : first;
  std::ostringstream w;
  if (!winner) {
    w << "the fuzzy model (" << cs[first.candidate].rules << " rules)";
    if (result.linear_checks.size() > 1)
      w << " and the next " << result.linear_checks.size() - 1 << " by hold-out score";
    w << " did not beat the linear one in " << ctx.options.linear_check_folds
      << "-fold blocked cross-validation (NDEI " << first.fuzzy_score << " vs "
      << first.linear_score << "): the linear model (" << LinearFitName(result) << ") is chosen";
    result.warnings.push_back(w.str());
    result.chosen = linear;
  } else if (*winner != result.chosen) {
    w << "the chosen fuzzy model (" << cs[result.chosen].rules << " rules) lost the "
      << ctx.options.linear_check_folds << "-fold blocked cross-validation to the linear one (NDEI "
      << first.fuzzy_score << " vs " << first.linear_score << "); the next by hold-out score, "
      << cs[*winner].rules << " rules, won it (" << result.linear_check.fuzzy_score
      << ") and is chosen";
    result.warnings.push_back(w.str());
    result.chosen = *winner;
  }
}

}  // namespace odonata::sysid
