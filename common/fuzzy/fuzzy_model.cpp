#include "fuzzy/fuzzy_model.hpp"

#include "fuzzy/fuzzy_model_state.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "contract/precondition.hpp"
#include "fuzzy/consequent_normal_equations.hpp"

namespace odonata::fuzzy {

namespace {
FuzzyModelConfig Checked(const FuzzyModelConfig& config) {
  const std::string p = config.Problems();
  if (!p.empty()) throw std::invalid_argument("fuzzy model: " + p);
  return config;
}
}  // namespace

std::string FuzzyModelConfig::Problems() const {
  std::string p;
  auto add = [&p](const std::string& line) {
    if (line.empty()) return;
    if (!p.empty()) p += "\n";
    p += line;
  };
  // Sizes are products in memory (rules × inputs²), so an absurd count is refused here, before
  // anything is allocated.
  if (inputs < 1 || inputs > 1000)
    add("inputs must be in [1, 1000], not " + std::to_string(inputs));
  add(entropy.Problems());
  if (!(forgetting > 0.0 && forgetting <= 1.0))
    add("forgetting factor must be in (0, 1], not " + std::to_string(forgetting));
  const auto finite_nonneg = [](double v) { return std::isfinite(v) && v >= 0.0; };
  if (!finite_nonneg(rates.centre) || !finite_nonneg(rates.sigma) ||
      !finite_nonneg(rates.output_width) ||
      !(rates.max_step > 0.0 && std::isfinite(rates.max_step)))
    add("learning rates must be finite and non-negative, max_step positive");
  return p;
}

FuzzyModel::FuzzyModel(const FuzzyModelConfig& config)
    : config_(Checked(config)),
      rules_(config.inputs, config.entropy.max_rules),
      consequent_(MakeConsequent(config.consequent, config.inputs, config.entropy.max_rules,
                                 config.forgetting)) {
  AllocateScratch();
}

FuzzyModel::FuzzyModel(const FuzzyModel& other)
    : config_(other.config_),
      rules_(other.rules_),
      consequent_(other.consequent_->Clone()),
      utility_sum_(other.utility_sum_),
      born_(other.born_),
      clock_(other.clock_),
      pruned_(other.pruned_),
      names_(other.names_) {
  AllocateScratch();
}

FuzzyModel& FuzzyModel::operator=(const FuzzyModel& other) {
  if (this != &other) {
    config_ = other.config_;
    rules_ = other.rules_;
    consequent_ = other.consequent_->Clone();
    utility_sum_ = other.utility_sum_;
    born_ = other.born_;
    clock_ = other.clock_;
    pruned_ = other.pruned_;
    names_ = other.names_;
    AllocateScratch();
  }
  return *this;
}

void FuzzyModel::AllocateScratch() {
  const int cap = config_.entropy.max_rules;
  gradient_factor_.resize(cap);
  grad_c_.resize(cap);
  grad_s_.resize(cap);
  if (utility_sum_.size() != cap) {
    utility_sum_ = Eigen::ArrayXd::Zero(cap);
    born_ = Eigen::Array<long long, Eigen::Dynamic, 1>::Zero(cap);
  }
  scratch_.weighted_distance.resize(0);
  scratch_.normalized.resize(0);
  rule_outputs_.resize(0);
}

void FuzzyModel::set_entropy_threshold(double h) {
  EntropyRuleConfig e = config_.entropy;
  e.threshold = h;
  const std::string p = e.Problems();
  if (!p.empty()) throw std::invalid_argument(p);
  config_.entropy.threshold = h;
}

void FuzzyModel::set_forgetting(double lambda) {
  FuzzyModelConfig c = config_;
  c.forgetting = lambda;
  const std::string p = c.Problems();
  if (!p.empty()) throw std::invalid_argument(p);
  config_.forgetting = lambda;
  consequent_->SetForgetting(lambda);
}

double FuzzyModel::utility(int rule) const {
  const long long age = clock_ - born_(rule);
  return age <= 0 ? 1.0 : utility_sum_(rule) / static_cast<double>(age);
}

int FuzzyModel::LeastUsefulRule() const {
  int worst = -1;
  double lowest = 0.0;
  for (int j = 0; j < rules_.rules(); ++j) {
    if (clock_ - born_(j) < config_.entropy.prune_min_age) continue;
    const double u = utility(j);
    if (worst < 0 || u < lowest) {
      worst = j;
      lowest = u;
    }
  }
  return worst;
}

void FuzzyModel::RemoveRule(int rule) {
  const int tail = rules_.rules() - rule - 1;
  rules_.RemoveRule(rule);
  consequent_->RemoveRule(rule);
  if (tail > 0) {
    utility_sum_.segment(rule, tail) = utility_sum_.segment(rule + 1, tail).eval();
    born_.segment(rule, tail) = born_.segment(rule + 1, tail).eval();
  }
  names_.erase(names_.begin() + rule);
  ++pruned_;
}

bool FuzzyModel::named() const {
  return std::any_of(names_.begin(), names_.end(), [](const RuleNames& n) { return !n.empty(); });
}

double FuzzyModel::Predict(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  if (rules_.rules() == 0) return 0.0;
  rules_.Evaluate(x, &scratch_);
  consequent_->RuleOutputs(x, rules_.rules(), &rule_outputs_);
  return (scratch_.normalized * rule_outputs_).sum();
}

double FuzzyModel::PredictWithDistance(const Eigen::Ref<const Eigen::VectorXd>& x,
                                       double* distance_widths) const {
  if (rules_.rules() == 0) {
    *distance_widths = std::numeric_limits<double>::infinity();
    return 0.0;
  }
  const double yhat = EvaluateInScratch(x);
  *distance_widths = std::sqrt(scratch_.min_distance);
  return yhat;
}

double FuzzyModel::NearestRuleDistance(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  if (rules_.rules() == 0) return std::numeric_limits<double>::infinity();
  rules_.Evaluate(x, &scratch_);
  return std::sqrt(scratch_.min_distance);
}

double FuzzyModel::MaxEntropy(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  rules_.Evaluate(x, &scratch_);
  return EntropyRuleGenerator::MaxEntropy(config_.entropy, rules_, scratch_, x);
}

void FuzzyModel::PremiseGradientOfInput(int i, double xi, const Eigen::Ref<const Eigen::ArrayXd>& g,
                                        Eigen::Ref<Eigen::ArrayXd> dc,
                                        Eigen::Ref<Eigen::ArrayXd> ds) const {
  const auto diff = xi - rules_.centres_of_input(i);
  const auto inv = rules_.inverse_variances_of_input(i);
  // ∂J/∂c_ji = g_j (x_i − c_ji)/(σ_ji² + ε);  ∂J/∂σ_ji = ∂J/∂c_ji · (x_i − c_ji) σ_ji/(σ_ji² + ε)
  dc = g * diff * inv;
  ds = dc * diff * rules_.sigmas_of_input(i) * inv;
}

LearnResult FuzzyModel::Learn(const Eigen::Ref<const Eigen::VectorXd>& x, double y, LearnMode mode,
                              double premise_rate_scale) {
  LearnResult result;
  const auto& ec = config_.entropy;
  rules_.Evaluate(x, &scratch_);
  result.max_entropy = EntropyRuleGenerator::MaxEntropy(ec, rules_, scratch_, x);
  const bool grow_mode = mode == LearnMode::kGrowAndTune;
  if (grow_mode) {
    ++clock_;
    if (EntropyRuleGenerator::IsNovel(ec, rules_, result.max_entropy)) {
      // A full rule base that prunes makes room by retiring its least useful rule, so a vehicle
      // that changes keeps learning instead of freezing its structure at the cap.
      if (rules_.rules() >= ec.max_rules && ec.prune_utility > 0.0) {
        const int worst = LeastUsefulRule();
        if (worst >= 0) {
          RemoveRule(worst);
          rules_.Evaluate(x, &scratch_);
        }
      }
      if (rules_.rules() < ec.max_rules) {
        const Eigen::VectorXd sigma = EntropyRuleGenerator::NewWidths(ec, rules_, x);
        consequent_->AddRule(x, y, scratch_.normalized);
        const int j = rules_.rules();
        rules_.AddRule(x, sigma);
        utility_sum_(j) = 0.0;
        born_(j) = clock_ - 1;
        names_.emplace_back();  // the model's own rule: no expert named it
        rules_.Evaluate(x, &scratch_);
        result.rule_added = true;
      }
    }
  }
  const int r = rules_.rules();
  if (r == 0) {
    result.error = -y;
    return result;
  }
  consequent_->RuleOutputs(x, r, &rule_outputs_);
  const Eigen::ArrayXd& phi = scratch_.normalized;
  const double yhat = (phi * rule_outputs_).sum();
  const double e = yhat - y;
  result.prediction = yhat;
  result.error = e;
  if (mode == LearnMode::kFrozen) return result;

  // Premise step from the pre-update parameters. Updating input i's centres and widths does not
  // change input i+1's gradient (g is computed once), so input-by-input is exact. Scratch arrays
  // are members sized to the capacity, so this loop never allocates.
  const auto& rates = config_.rates;
  const double lo = -rates.max_step;
  const double hi = rates.max_step;
  const double rate_c = rates.centre * premise_rate_scale;
  const double rate_s = rates.sigma * premise_rate_scale;
  auto g = gradient_factor_.head(r);
  g = e * (rule_outputs_ - yhat) * phi;
  const double sigma_min = ec.sigma_min;
  auto dc = grad_c_.head(r);
  auto ds = grad_s_.head(r);
  for (int i = 0; i < config_.inputs; ++i) {
    PremiseGradientOfInput(i, x(i), g, dc, ds);
    auto c = rules_.mutable_centres().col(i).head(r);
    auto sg = rules_.mutable_sigmas().col(i).head(r);
    c -= (rate_c * dc).min(hi).max(lo);
    sg = (sg - (rate_s * ds).min(hi).max(lo)).max(sigma_min);
    rules_.mutable_inverse_variances().col(i).head(r) = 1.0 / (sg.square() + kEpsilon);
  }
  if (rates.output_width > 0.0) {
    auto& s = rules_.mutable_output_widths();
    const Eigen::ArrayXd gs = -g * 2.0 * s.head(r) * rules_.inverse_output_weights();
    s.head(r) =
        (s.head(r) - (rates.output_width * premise_rate_scale * gs).min(hi).max(lo)).max(0.05);
    rules_.RefreshCaches();
  }
  if (mode != LearnMode::kTunePremises) consequent_->Update(x, phi, e, y);
  // Utility is only bookkept when pruning is on: it costs a pass over the rules per sample.
  if (grow_mode && ec.prune_utility > 0.0) {
    utility_sum_.head(r) += phi;
    if (r > 1) {
      const int worst = LeastUsefulRule();
      if (worst >= 0 && utility(worst) < ec.prune_utility) RemoveRule(worst);
    }
  }
  return result;
}

Gradients FuzzyModel::ComputeGradients(const Eigen::Ref<const Eigen::VectorXd>& x, double y) const {
  const int r = rules_.rules();
  const int n = config_.inputs;
  Gradients grad;
  grad.centres = Eigen::ArrayXXd::Zero(r, n);
  grad.sigmas = Eigen::ArrayXXd::Zero(r, n);
  grad.output_widths = Eigen::ArrayXd::Zero(r);
  if (r == 0) return grad;
  Inference inf;
  rules_.Evaluate(x, &inf);
  Eigen::ArrayXd outputs;
  consequent_->RuleOutputs(x, r, &outputs);
  const Eigen::ArrayXd& phi = inf.normalized;
  const double yhat = (phi * outputs).sum();
  const double e = yhat - y;
  const Eigen::ArrayXd g = e * (outputs - yhat) * phi;
  Eigen::ArrayXd dc(r), ds(r);
  for (int i = 0; i < n; ++i) {
    PremiseGradientOfInput(i, x(i), g, dc, ds);
    grad.centres.col(i) = dc;
    grad.sigmas.col(i) = ds;
  }
  grad.output_widths = -g * 2.0 * rules_.output_widths() * rules_.inverse_output_weights();
  grad.consequents = consequent_->Gradient(x, phi, e);
  return grad;
}

void FuzzyModel::AccumulatePremiseGradient(const Eigen::Ref<const Eigen::VectorXd>& x, double y,
                                           Eigen::ArrayXXd* gc, Eigen::ArrayXXd* gs) const {
  const int r = rules_.rules();
  if (r == 0) return;
  const double yhat = EvaluateInScratch(x);
  AddPremiseGradient(x, yhat - y, yhat, gc, gs);
}

void FuzzyModel::AccumulatePremiseGradientAt(const Eigen::Ref<const Eigen::VectorXd>& x,
                                             const Eigen::Ref<const Eigen::ArrayXd>& phi, double y,
                                             Eigen::ArrayXXd* gc, Eigen::ArrayXXd* gs) const {
  const int r = rules_.rules();
  if (r == 0) return;
  ODONATA_EXPECTS(phi.size() == r);
  scratch_.normalized = phi;
  consequent_->RuleOutputs(x, r, &rule_outputs_);
  const double yhat = (scratch_.normalized * rule_outputs_).sum();  // EvaluateInScratch's sum
  AddPremiseGradient(x, yhat - y, yhat, gc, gs);
}

void FuzzyModel::AddPremiseGradient(const Eigen::Ref<const Eigen::VectorXd>& x, double weight,
                                    double yhat, Eigen::ArrayXXd* gc, Eigen::ArrayXXd* gs) const {
  const int r = rules_.rules();
  auto g = gradient_factor_.head(r);
  g = weight * (rule_outputs_ - yhat) * scratch_.normalized.head(r);
  auto dc = grad_c_.head(r);
  auto ds = grad_s_.head(r);
  for (int i = 0; i < config_.inputs; ++i) {
    PremiseGradientOfInput(i, x(i), g, dc, ds);
    gc->col(i).head(r) += dc;
    gs->col(i).head(r) += ds;
  }
}

double FuzzyModel::EvaluateInScratch(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  rules_.Evaluate(x, &scratch_);
  consequent_->RuleOutputs(x, rules_.rules(), &rule_outputs_);
  return (scratch_.normalized * rule_outputs_).sum();
}

double FuzzyModel::PredictWithInputGradient(const Eigen::Ref<const Eigen::VectorXd>& x,
                                            Eigen::Ref<Eigen::VectorXd> dydx) const {
  dydx.setZero();
  const int r = rules_.rules();
  if (r == 0) return 0.0;
  const double yhat = EvaluateInScratch(x);
  const Eigen::ArrayXd& phi = scratch_.normalized;
  // ∂ŷ/∂x_i = Σ_j φ_j ∂y_j/∂x_i − Σ_j ∂ŷ/∂c_ji: moving x is moving every centre the other way.
  auto g = gradient_factor_.head(r);
  g = (rule_outputs_ - yhat) * phi;
  auto dc = grad_c_.head(r);
  auto ds = grad_s_.head(r);
  for (int i = 0; i < config_.inputs; ++i) {
    PremiseGradientOfInput(i, x(i), g, dc, ds);
    dydx(i) = -dc.sum();
  }
  consequent_->AddInputGradient(phi, dydx);
  return yhat;
}

void FuzzyModel::AccumulateOutputGradient(const Eigen::Ref<const Eigen::VectorXd>& x, double weight,
                                          Eigen::ArrayXXd* gc, Eigen::ArrayXXd* gs,
                                          Eigen::VectorXd* gq) const {
  const int r = rules_.rules();
  if (r == 0 || weight == 0.0) return;
  const double yhat = EvaluateInScratch(x);
  if (gc != nullptr && gs != nullptr) AddPremiseGradient(x, weight, yhat, gc, gs);
  *gq += consequent_->Gradient(x, scratch_.normalized, weight);
}

void FuzzyModel::StepPremises(const Eigen::ArrayXXd& dc, const Eigen::ArrayXXd& ds) {
  const int r = rules_.rules();
  rules_.mutable_centres().topRows(r) += dc.topRows(r);
  rules_.mutable_sigmas().topRows(r) =
      (rules_.mutable_sigmas().topRows(r) + ds.topRows(r)).max(config_.entropy.sigma_min);
  rules_.RefreshCaches();
}

int FuzzyModel::PruneUnsupported(const Eigen::Ref<const Eigen::MatrixXd>& X, double per_parameter) {
  const int r = rules_.rules();
  if (r < 2 || X.rows() == 0 || !(per_parameter > 0.0)) return 0;
  Eigen::ArrayXd support = Eigen::ArrayXd::Zero(r);
  Inference inf;
  for (Eigen::Index k = 0; k < X.rows(); ++k) {
    rules_.Evaluate(X.row(k).transpose(), &inf);
    support += inf.normalized.head(r);
  }
  const double need = per_parameter * consequent_->LeastSquaresWidth();
  Eigen::Index best = 0;
  support.maxCoeff(&best);
  int removed = 0;
  // From the last rule down, so the indices still to visit do not move.
  for (int j = r - 1; j >= 0; --j) {
    if (j == best || !(support(j) < need)) continue;
    RemoveRule(j);
    ++removed;
  }
  return removed;
}

void FuzzyModel::DesignRow(const Eigen::Ref<const Eigen::VectorXd>& x,
                           Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> row,
                           Inference* inference, Eigen::VectorXd* z) const {
  const int r = rules_.rules();
  const int w = consequent_->LeastSquaresWidth();
  rules_.Evaluate(x, inference);
  z->resize(w);
  consequent_->LeastSquaresRow(x, *z);
  for (int j = 0; j < r; ++j) row.segment(j * w, w) = inference->normalized(j) * z->transpose();
}

bool FuzzyModel::RefineConsequents(const Eigen::Ref<const Eigen::MatrixXd>& X,
                                   const Eigen::Ref<const Eigen::VectorXd>& Y, double ridge,
                                   double deviation_ridge, double* residual_squares,
                                   Eigen::ArrayXXd* firings) {
  const int r = rules_.rules();
  if (r == 0 || X.rows() == 0) return false;
  const int w = consequent_->LeastSquaresWidth();
  // θ_j = g + δ_j with the deviations' ridge: Σ_j φ_j = 1, so row k is [z_k, φ_k1 z_k, …] over
  // (g, δ_1 … δ_R), and the model becomes the global one (ARX) as the ridge grows.
  const SharedPart shared =
      deviation_ridge > 0.0 && r > 1 ? SharedPart::kGlobal : SharedPart::kNone;
  ConsequentNormalEquations normal(r, w, shared);
  // Rows in blocks: the firings and regressors of a block, not of the whole record, in memory.
  constexpr Eigen::Index kBlockRows = 2048;
  const Eigen::Index block = std::min(kBlockRows, X.rows());
  Eigen::ArrayXXd phi_block;
  if (firings)
    firings->resize(X.rows(), r);
  else
    phi_block.resize(block, r);
  Eigen::MatrixXd zs(block, w);
  Eigen::VectorXd z(w);
  Inference inf;
  for (Eigen::Index start = 0; start < X.rows(); start += block) {
    const Eigen::Index rows = std::min(block, X.rows() - start);
    auto phi = firings ? firings->middleRows(start, rows) : phi_block.topRows(rows);
    for (Eigen::Index k = 0; k < rows; ++k) {
      const auto x = X.row(start + k).transpose();
      rules_.Evaluate(x, &inf);
      phi.row(k) = inf.normalized.transpose();
      consequent_->LeastSquaresRow(x, z);
      zs.row(k) = z.transpose();
    }
    normal.AddRows(phi, zs.topRows(rows), Y.segment(start, rows));
  }
  const Eigen::VectorXd theta =
      normal.Solve(ridge, shared == SharedPart::kGlobal ? deviation_ridge : 0.0, residual_squares);
  if (!theta.allFinite()) return false;  // keep the online solution rather than install NaN
  consequent_->SetFromLeastSquares(theta);
  return true;
}

}  // namespace odonata::fuzzy
