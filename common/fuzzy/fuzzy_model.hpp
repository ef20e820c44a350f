#pragma once
// The five-layer entropy fuzzy network: antecedents, consequents, structure and parameter
// learning for one output, in scaled units (scaling lives in sysid::NarxModel).

#include <memory>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "fuzzy/consequent.hpp"
#include "fuzzy/entropy_rule_generator.hpp"
#include "fuzzy/gaussian_rule_base.hpp"

namespace odonata::fuzzy {

/// Gradient-descent rates for the antecedents (identifier.md §2, "stability that works").
struct PremiseLearningRates {
  double centre = 0.02;       ///< α_c, scaled units.
  double sigma = 0.02;        ///< α_σ.
  double output_width = 0.0;  ///< α_s; 0 keeps s_j = 1 (the paper's default behaviour).
  double max_step = 0.05;     ///< Each parameter's step is clipped to ±max_step.
};

struct FuzzyModelConfig {
  int inputs = 1;
  ConsequentKind consequent = ConsequentKind::kSingleton;
  EntropyRuleConfig entropy;
  PremiseLearningRates rates;
};

/// What one online step did.
struct LearnResult {
  double prediction = 0.0;   ///< ŷ before the parameter update (after any rule creation).
  double error = 0.0;        ///< ŷ − y.
  double max_entropy = 0.0;  ///< max_j H_j before any rule creation.
  bool rule_added = false;
};

/// Which parameters a learning step may change.
enum class LearnMode {
  kGrowAndTune,   ///< entropy rule creation, then one gradient/consequent step (online default)
  kTune,          ///< no new rules; premises and consequents learn
  kTunePremises,  ///< no new rules; consequents frozen (the hybrid rule's gradient half)
  kFrozen,        ///< nothing changes; Learn() only reports
};

/// ∂J/∂θ for J = ½(ŷ − y)², laid out like the parameters (active rules only).
struct Gradients {
  Eigen::ArrayXXd centres;       ///< rules × inputs
  Eigen::ArrayXXd sigmas;        ///< rules × inputs
  Eigen::ArrayXd output_widths;  ///< rules
  Eigen::VectorXd consequents;   ///< Consequent::Parameters() layout
};

/// A multi-input single-output entropy fuzzy model. Deterministic: the same sequence of
/// samples gives the same parameters bit for bit (no randomness, fixed evaluation order).
/// Not thread-safe: Predict() reuses internal scratch space to stay allocation-free.
class FuzzyModel {
 public:
  /// @pre config.inputs ≥ 1, config.entropy.max_rules ≥ 1.
  explicit FuzzyModel(const FuzzyModelConfig& config);
  FuzzyModel(const FuzzyModel& other);
  FuzzyModel& operator=(const FuzzyModel& other);
  FuzzyModel(FuzzyModel&&) noexcept = default;
  FuzzyModel& operator=(FuzzyModel&&) noexcept = default;

  /// ŷ = Σ_j φ_j y_j(x); 0 when there is no rule yet.
  double Predict(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// max_j H_j at x (0 with no rules).
  double MaxEntropy(const Eigen::Ref<const Eigen::VectorXd>& x) const;

  /// One online step on the sample (x, y): maybe grow a rule, predict, then update.
  LearnResult Learn(const Eigen::Ref<const Eigen::VectorXd>& x, double y,
                    LearnMode mode = LearnMode::kGrowAndTune);

  /// Analytic gradients at (x, y) with the current parameters (for checks and tools).
  Gradients ComputeGradients(const Eigen::Ref<const Eigen::VectorXd>& x, double y) const;

  /// The ANFIS forward pass: with the antecedents fixed, sets every consequent to the global
  /// ridge-regularised least-squares optimum over the rows of X (samples × inputs) and Y.
  /// `ridge` is relative to the mean diagonal of ΦᵀΦ.
  void RefineConsequents(const Eigen::Ref<const Eigen::MatrixXd>& X,
                         const Eigen::Ref<const Eigen::VectorXd>& Y, double ridge = 1e-8);

  int rules() const { return rules_.rules(); }
  int inputs() const { return config_.inputs; }
  const FuzzyModelConfig& config() const { return config_; }
  const GaussianRuleBase& rule_base() const { return rules_; }
  GaussianRuleBase& mutable_rule_base() { return rules_; }
  const Consequent& consequent() const { return *consequent_; }
  Consequent& mutable_consequent() { return *consequent_; }
  /// Changes H̄ for later samples (an online control command); existing rules stay.
  void set_entropy_threshold(double h);

  nlohmann::json ToJson() const;
  /// @throws std::runtime_error with the offending field on malformed content.
  static FuzzyModel FromJson(const nlohmann::json& j);

 private:
  FuzzyModelConfig config_;
  GaussianRuleBase rules_;
  std::unique_ptr<Consequent> consequent_;
  EntropyRuleGenerator generator_;
  void AllocateScratch();

  // Scratch space, sized once, so Predict() and Learn() never allocate.
  mutable Inference scratch_;
  mutable Eigen::ArrayXd rule_outputs_;
  Eigen::ArrayXd gradient_factor_;  // g_j
  Eigen::ArrayXd diff_;             // x_i − c_ji for one input
  Eigen::ArrayXd scaled_diff_;      // g_j (x_i − c_ji) / (σ_ji² + ε)
};

}  // namespace odonata::fuzzy
