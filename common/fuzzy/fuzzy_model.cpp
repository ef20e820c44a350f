#include "fuzzy/fuzzy_model.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <nlohmann/json.hpp>

namespace odonata::fuzzy {

FuzzyModel::FuzzyModel(const FuzzyModelConfig& config)
    : config_(config),
      rules_(config.inputs, config.entropy.max_rules),
      consequent_(MakeConsequent(config.consequent, config.inputs, config.entropy.max_rules)),
      generator_(config.entropy) {
  assert(config.inputs >= 1 && config.entropy.max_rules >= 1);
  AllocateScratch();
}

FuzzyModel::FuzzyModel(const FuzzyModel& other)
    : config_(other.config_),
      rules_(other.rules_),
      consequent_(other.consequent_->Clone()),
      generator_(other.generator_) {
  AllocateScratch();
}

FuzzyModel& FuzzyModel::operator=(const FuzzyModel& other) {
  if (this != &other) {
    config_ = other.config_;
    rules_ = other.rules_;
    consequent_ = other.consequent_->Clone();
    generator_ = other.generator_;
    AllocateScratch();
  }
  return *this;
}

void FuzzyModel::AllocateScratch() {
  const int cap = config_.entropy.max_rules;
  gradient_factor_.resize(cap);
  diff_.resize(cap);
  scaled_diff_.resize(cap);
  scratch_.weighted_distance.resize(0);
  scratch_.normalized.resize(0);
  rule_outputs_.resize(0);
}

void FuzzyModel::set_entropy_threshold(double h) {
  config_.entropy.threshold = h;
  generator_.set_threshold(h);
}

double FuzzyModel::Predict(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  if (rules_.rules() == 0) return 0.0;
  rules_.Evaluate(x, &scratch_);
  consequent_->RuleOutputs(x, rules_.rules(), &rule_outputs_);
  return (scratch_.normalized * rule_outputs_).sum();
}

double FuzzyModel::MaxEntropy(const Eigen::Ref<const Eigen::VectorXd>& x) const {
  rules_.Evaluate(x, &scratch_);
  return generator_.MaxEntropy(rules_, scratch_, x);
}

LearnResult FuzzyModel::Learn(const Eigen::Ref<const Eigen::VectorXd>& x, double y,
                              LearnMode mode) {
  LearnResult result;
  rules_.Evaluate(x, &scratch_);
  result.max_entropy = generator_.MaxEntropy(rules_, scratch_, x);
  if (mode == LearnMode::kGrowAndTune && generator_.ShouldGrow(rules_, result.max_entropy)) {
    const Eigen::VectorXd sigma = generator_.NewWidths(rules_, x);
    consequent_->AddRule(x, y, scratch_.normalized);
    rules_.AddRule(x, sigma);
    rules_.Evaluate(x, &scratch_);
    result.rule_added = true;
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

  // Premise step, from the pre-update parameters: g_j = e (y_j − ŷ) φ_j is the common factor
  // of ∂J/∂c, ∂J/∂σ and ∂J/∂s (identifier.md §2). Scratch arrays are members sized to the
  // capacity, so this loop never allocates.
  const auto& rates = config_.rates;
  const double lo = -rates.max_step;
  const double hi = rates.max_step;
  auto g = gradient_factor_.head(r);
  g = e * (rule_outputs_ - yhat) * phi;
  const double sigma_min = config_.entropy.sigma_min;
  auto diff = diff_.head(r);
  auto gd = scaled_diff_.head(r);
  for (int i = 0; i < config_.inputs; ++i) {
    auto c = rules_.mutable_centres().col(i).head(r);
    auto sg = rules_.mutable_sigmas().col(i).head(r);
    auto inv = rules_.mutable_inverse_variances().col(i).head(r);
    diff = x(i) - c;
    gd = g * diff * inv;  // ∂J/∂c_ji
    c -= (rates.centre * gd).min(hi).max(lo);
    // ∂J/∂σ_ji = ∂J/∂c_ji · (x_i − c_ji) σ_ji / (σ_ji² + ε)
    sg = (sg - (rates.sigma * gd * diff * sg * inv).min(hi).max(lo)).max(sigma_min);
    inv = 1.0 / (sg.square() + kEpsilon);
  }
  if (rates.output_width > 0.0) {
    auto& s = rules_.mutable_output_widths();
    const Eigen::ArrayXd ds = -g * 2.0 * s.head(r) * rules_.inverse_output_weights();
    s.head(r) = (s.head(r) - (rates.output_width * ds).min(hi).max(lo)).max(0.05);
    rules_.RefreshCaches();
  }
  if (mode != LearnMode::kTunePremises) consequent_->Update(x, phi, e, y);
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
  for (int i = 0; i < n; ++i) {
    const Eigen::ArrayXd diff = x(i) - rules_.centres_of_input(i);
    const Eigen::ArrayXd inv = rules_.inverse_variances_of_input(i);
    grad.centres.col(i) = g * diff * inv;
    grad.sigmas.col(i) = g * diff.square() * rules_.sigmas_of_input(i) * inv.square();
  }
  grad.output_widths = -g * 2.0 * rules_.output_widths() * rules_.inverse_output_weights();
  grad.consequents = consequent_->Gradient(x, phi, e);
  return grad;
}

void FuzzyModel::RefineConsequents(const Eigen::Ref<const Eigen::MatrixXd>& X,
                                   const Eigen::Ref<const Eigen::VectorXd>& Y, double ridge) {
  const int r = rules_.rules();
  if (r == 0 || X.rows() == 0) return;
  const int w = consequent_->LeastSquaresWidth();
  const Eigen::Index m = static_cast<Eigen::Index>(r) * w;
  // Row k of Φ is [φ_k1 z_k, …, φ_kR z_k]. Accumulating ΦᵀΦ in blocks of rows keeps memory at
  // O(block · m) for long records while the products still run as matrix–matrix kernels.
  constexpr Eigen::Index kBlock = 2048;
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  Eigen::MatrixXd phi_rows(std::min<Eigen::Index>(kBlock, X.rows()), m);
  Eigen::VectorXd z(w);
  Inference inf;
  for (Eigen::Index start = 0; start < X.rows(); start += kBlock) {
    const Eigen::Index rows = std::min<Eigen::Index>(kBlock, X.rows() - start);
    for (Eigen::Index k = 0; k < rows; ++k) {
      const Eigen::VectorXd xk = X.row(start + k).transpose();
      rules_.Evaluate(xk, &inf);
      consequent_->LeastSquaresRow(xk, z);
      for (int j = 0; j < r; ++j)
        phi_rows.block(k, j * w, 1, w) = inf.normalized(j) * z.transpose();
    }
    const auto block = phi_rows.topRows(rows);
    normal.selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
    rhs.noalias() += block.transpose() * Y.segment(start, rows);
  }
  const double mean_diag = normal.diagonal().mean();
  normal.diagonal().array() += ridge * mean_diag + 1e-12;
  const Eigen::VectorXd theta = normal.selfadjointView<Eigen::Lower>().ldlt().solve(rhs);
  if (!theta.allFinite()) return;  // keep the online solution rather than install NaN
  consequent_->SetFromLeastSquares(theta);
}

nlohmann::json FuzzyModel::ToJson() const {
  nlohmann::json j;
  j["inputs"] = config_.inputs;
  const auto& e = config_.entropy;
  j["entropy"] = {{"threshold", e.threshold},
                  {"max_rules", e.max_rules},
                  {"kappa", e.kappa},
                  {"sigma_init", e.sigma_init},
                  {"sigma_min", e.sigma_min},
                  {"sigma_max", e.sigma_max},
                  {"measure", e.measure == EntropyMeasure::kFiring ? "firing" : "per_input"}};
  const auto& a = config_.rates;
  j["rates"] = {{"centre", a.centre},
                {"sigma", a.sigma},
                {"output_width", a.output_width},
                {"max_step", a.max_step}};
  nlohmann::json rules = nlohmann::json::array();
  for (int r = 0; r < rules_.rules(); ++r) {
    std::vector<double> c(static_cast<std::size_t>(config_.inputs));
    std::vector<double> s(c.size());
    for (int i = 0; i < config_.inputs; ++i) {
      c[static_cast<std::size_t>(i)] = rules_.centre(r, i);
      s[static_cast<std::size_t>(i)] = rules_.sigma(r, i);
    }
    rules.push_back({{"centre", c}, {"sigma", s}, {"output_width", rules_.output_width(r)}});
  }
  j["rules"] = rules;
  j["consequent"] = consequent_->ToJson();
  return j;
}

FuzzyModel FuzzyModel::FromJson(const nlohmann::json& j) {
  try {
    FuzzyModelConfig cfg;
    cfg.inputs = j.at("inputs").get<int>();
    const auto& e = j.at("entropy");
    cfg.entropy.threshold = e.at("threshold").get<double>();
    cfg.entropy.max_rules = e.at("max_rules").get<int>();
    cfg.entropy.kappa = e.at("kappa").get<double>();
    cfg.entropy.sigma_init = e.at("sigma_init").get<double>();
    cfg.entropy.sigma_min = e.at("sigma_min").get<double>();
    cfg.entropy.sigma_max = e.at("sigma_max").get<double>();
    const auto measure = e.at("measure").get<std::string>();
    if (measure != "firing" && measure != "per_input") {
      throw std::runtime_error("entropy.measure must be firing or per_input, not '" + measure +
                               "'");
    }
    cfg.entropy.measure = measure == "firing" ? EntropyMeasure::kFiring : EntropyMeasure::kPerInput;
    const auto& a = j.at("rates");
    cfg.rates.centre = a.at("centre").get<double>();
    cfg.rates.sigma = a.at("sigma").get<double>();
    cfg.rates.output_width = a.at("output_width").get<double>();
    cfg.rates.max_step = a.at("max_step").get<double>();
    const auto& cons = j.at("consequent");
    cfg.consequent = ConsequentKindFromString(cons.at("kind").get<std::string>());
    if (cfg.inputs < 1 || cfg.entropy.max_rules < 1) {
      throw std::runtime_error("inputs and entropy.max_rules must be at least 1");
    }
    FuzzyModel model(cfg);
    const auto& rules = j.at("rules");
    if (static_cast<int>(rules.size()) > cfg.entropy.max_rules) {
      throw std::runtime_error("more rules than entropy.max_rules");
    }
    for (const auto& rule : rules) {
      const auto c = rule.at("centre").get<std::vector<double>>();
      const auto s = rule.at("sigma").get<std::vector<double>>();
      if (static_cast<int>(c.size()) != cfg.inputs || static_cast<int>(s.size()) != cfg.inputs) {
        throw std::runtime_error("a rule has the wrong number of centres or widths");
      }
      for (double v : c)
        if (!std::isfinite(v)) throw std::runtime_error("a rule centre is not finite");
      for (double v : s)
        if (!std::isfinite(v) || v <= 0.0) throw std::runtime_error("a rule width is not positive");
      model.rules_.AddRule(Eigen::Map<const Eigen::VectorXd>(c.data(), cfg.inputs),
                           Eigen::Map<const Eigen::VectorXd>(s.data(), cfg.inputs),
                           rule.at("output_width").get<double>());
    }
    model.consequent_ = ConsequentFromJson(cons, cfg.inputs, cfg.entropy.max_rules);
    if (model.consequent_->rules() != model.rules_.rules()) {
      throw std::runtime_error("consequent count differs from the rule count");
    }
    return model;
  } catch (const nlohmann::json::exception& ex) {
    throw std::runtime_error(std::string("fuzzy model: ") + ex.what());
  }
}

}  // namespace odonata::fuzzy
