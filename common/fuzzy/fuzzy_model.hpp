#pragma once
// The five-layer entropy fuzzy network: antecedents, consequents, structure and parameter
// learning for one output, in scaled units (scaling lives in sysid::NarxModel).
// docs/identifier.md §1–§6.

#include <memory>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "fuzzy/consequent.hpp"
#include "fuzzy/entropy_rule_generator.hpp"
#include "fuzzy/gaussian_rule_base.hpp"
#include "fuzzy/rule_names.hpp"

namespace odonata::fuzzy {

/// Gradient-descent rates for the antecedents (docs/identifier.md §3).
struct PremiseLearningRates {
  double centre = 0.02;       ///< α_c, scaled units.
  double sigma = 0.02;        ///< α_σ.
  double output_width = 0.0;  ///< α_s; 0 keeps s_j = 1 (the paper's default behaviour).
  double max_step = 0.05;     ///< Each parameter's step is clipped to ±max_step.
};

struct FuzzyModelConfig {
  int inputs = 1;
  ConsequentKind consequent = ConsequentKind::kLinear;
  EntropyRuleConfig entropy;
  PremiseLearningRates rates;
  /// RLS forgetting factor λ ∈ (0, 1] of linear consequents; 1 never forgets.
  double forgetting = 1.0;

  /// Every problem with the configuration, one per line ("" when valid).
  std::string Problems() const;
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
struct FuzzyModelState;  // fuzzy_model_state.hpp

class FuzzyModel {
 public:
  /// @throws std::invalid_argument listing every problem of config (see Problems()).
  explicit FuzzyModel(const FuzzyModelConfig& config);
  FuzzyModel(const FuzzyModel& other);
  FuzzyModel& operator=(const FuzzyModel& other);
  FuzzyModel(FuzzyModel&&) noexcept = default;
  FuzzyModel& operator=(FuzzyModel&&) noexcept = default;

  /// ŷ = Σ_j φ_j y_j(x); 0 when there is no rule yet.
  double Predict(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// ŷ at x, and in `distance_widths` how far x lies from its nearest rule (Mahalanobis, in
  /// rule widths; +∞ with no rule): where the data the rules were fitted on ends (DataEnvelope).
  double PredictWithDistance(const Eigen::Ref<const Eigen::VectorXd>& x,
                             double* distance_widths) const;
  /// How far x lies from its nearest rule, in rule widths (+∞ with no rule).
  double NearestRuleDistance(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// max_j H_j at x (0 with no rules).
  double MaxEntropy(const Eigen::Ref<const Eigen::VectorXd>& x) const;

  /// One online step on the sample (x, y): maybe grow (or replace) a rule, predict, then update.
  /// `premise_rate_scale` multiplies the premise rates (the offline trainer's adaptive step).
  LearnResult Learn(const Eigen::Ref<const Eigen::VectorXd>& x, double y,
                    LearnMode mode = LearnMode::kGrowAndTune, double premise_rate_scale = 1.0);

  /// Analytic gradients at (x, y) with the current parameters (for checks and tools).
  Gradients ComputeGradients(const Eigen::Ref<const Eigen::VectorXd>& x, double y) const;

  /// Adds ∂J/∂c and ∂J/∂σ at (x, y) to gc and gs (rules × inputs), through the same kernel
  /// Learn() steps with: the batch gradient of the offline premise step.
  void AccumulatePremiseGradient(const Eigen::Ref<const Eigen::VectorXd>& x, double y,
                                 Eigen::ArrayXXd* gc, Eigen::ArrayXXd* gs) const;
  /// The same with x's normalised firings `phi` (rules) already known — a least-squares pass at
  /// the same premises kept them (RefineConsequents' `firings`): bit for bit the same sums.
  void AccumulatePremiseGradientAt(const Eigen::Ref<const Eigen::VectorXd>& x,
                                   const Eigen::Ref<const Eigen::ArrayXd>& phi, double y,
                                   Eigen::ArrayXXd* gc, Eigen::ArrayXXd* gs) const;
  /// ŷ at x, and ∂ŷ/∂x in `dydx` (sized inputs()): the sensitivity a free run passes back
  /// through its own lagged predictions (simulation-error training, docs/identifier.md §12).
  double PredictWithInputGradient(const Eigen::Ref<const Eigen::VectorXd>& x,
                                  Eigen::Ref<Eigen::VectorXd> dydx) const;
  /// Adds weight · ∂ŷ/∂θ at x to gc, gs (rules × inputs) and gq (Consequent::Parameters()
  /// layout), through the premise-gradient kernel Learn() uses; weight = ŷ − y gives ∂J/∂θ.
  /// gc and gs null: the consequents' part alone (the kernel is skipped).
  void AccumulateOutputGradient(const Eigen::Ref<const Eigen::VectorXd>& x, double weight,
                                Eigen::ArrayXXd* gc, Eigen::ArrayXXd* gs,
                                Eigen::VectorXd* gq) const;
  /// Moves centres by dc and widths by ds (rules × inputs), widths floored at σ_min.
  void StepPremises(const Eigen::ArrayXXd& dc, const Eigen::ArrayXXd& ds);

  /// The consequents' least-squares design row at x: [φ_1(x) z(x), …, φ_R(x) z(x)], z the
  /// consequent's regressor (Consequent::LeastSquaresRow), written into `row` (R · width).
  /// The row the consequent tracker (sysid/estimation) solves for, one sample at a time;
  /// RefineConsequents gathers the same rows tile by tile over the rules that fire
  /// (ConsequentNormalEquations). `inference` and `z` are scratch.
  void DesignRow(const Eigen::Ref<const Eigen::VectorXd>& x,
                 Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> row, Inference* inference,
                 Eigen::VectorXd* z) const;
  /// The ANFIS forward pass: with the antecedents fixed, sets every consequent to the global
  /// ridge-regularised least-squares optimum over the rows of X (samples × inputs) and Y, solved
  /// by normal equations gathered from the rules that fire (ConsequentNormalEquations). `ridge` is
  /// relative to the mean squared column norm of Φ. @return false (model unchanged) if the solve
  /// failed. `deviation_ridge` > 0 writes each rule's consequent as one global part plus its own
  /// deviation, and puts that ridge (relative, like `ridge`) on the deviations only: a rule the
  /// data hardly supports stays near the global linear model instead of fitting noise, and the
  /// model becomes that global model (ARX) as the ridge grows (docs/identifier.md §6.1).
  /// `residual_squares`, if given, receives the training loss Σ (ŷ − y)² the solution leaves
  /// (from the normal equations, so the caller needs no pass of its own); `firings`, if given,
  /// every row's normalised firings (rows × rules) at these premises.
  bool RefineConsequents(const Eigen::Ref<const Eigen::MatrixXd>& X,
                         const Eigen::Ref<const Eigen::VectorXd>& Y, double ridge = 1e-10,
                         double deviation_ridge = 0.0, double* residual_squares = nullptr,
                         Eigen::ArrayXXd* firings = nullptr);

  /// Removes every rule whose support — its normalised firing summed over the rows of X — is
  /// below `per_parameter` times its consequent's least-squares width (1 singleton, inputs + 1
  /// linear): fewer effective samples than the parameters the consequent solve estimates for it
  /// cannot determine them, and such a rule fits their noise (docs/identifier.md §6.1). The
  /// best-supported rule always stays. @return the rules removed.
  int PruneUnsupported(const Eigen::Ref<const Eigen::MatrixXd>& X, double per_parameter);

  int rules() const { return rules_.rules(); }
  /// Rule `rule`'s names, when an expert gave them (RuleNames); empty for the model's own rules.
  const RuleNames& names(int rule) const { return names_.at(static_cast<std::size_t>(rule)); }
  bool named() const;  ///< some rule has a name
  int inputs() const { return config_.inputs; }
  const FuzzyModelConfig& config() const { return config_; }
  const GaussianRuleBase& rule_base() const { return rules_; }
  GaussianRuleBase& mutable_rule_base() { return rules_; }
  const Consequent& consequent() const { return *consequent_; }
  Consequent& mutable_consequent() { return *consequent_; }
  /// Changes H̄ for later samples (an online control command); existing rules stay.
  /// @throws std::invalid_argument outside [0, kMaxRuleEntropy].
  void set_entropy_threshold(double h);
  /// Changes the RLS forgetting factor. @throws std::invalid_argument outside (0, 1].
  void set_forgetting(double lambda);
  /// Mean normalised firing of rule j since its creation (eTS+ utility); 1 for a rule born now.
  double utility(int rule) const;
  /// Samples seen in kGrowAndTune mode (the clock of rule ages).
  long long age_clock() const { return clock_; }
  /// Rules removed so far by pruning or replacement.
  long long rules_pruned() const { return pruned_; }

  /// The whole model as plain data (fuzzy_model_state.hpp): what files and snapshots carry.
  FuzzyModelState State() const;
  /// Rebuilds a model from State(); the one place a saved or received model is checked.
  /// @throws std::runtime_error naming the offending field.
  static FuzzyModel FromState(const FuzzyModelState& state);

  /// State() as JSON (a model file's per-output block) and back.
  nlohmann::json ToJson() const;
  /// @throws std::runtime_error with the offending field on malformed content.
  static FuzzyModel FromJson(const nlohmann::json& j);
  /// The JSON read into a state, unchecked (FromState checks it).
  /// @throws std::runtime_error when a field is missing or of the wrong type.
  static FuzzyModelState StateFromJson(const nlohmann::json& j);

 private:
  FuzzyModelConfig config_;
  GaussianRuleBase rules_;
  std::unique_ptr<Consequent> consequent_;
  void AllocateScratch();
  /// The one premise-gradient kernel (docs/identifier.md §3), used by Learn() and
  /// ComputeGradients(): for input i over the first r rules, given g_j = e (y_j − ŷ) φ_j,
  /// writes ∂J/∂c_ji into dc and ∂J/∂σ_ji into ds.
  void PremiseGradientOfInput(int i, double xi, const Eigen::Ref<const Eigen::ArrayXd>& g,
                              Eigen::Ref<Eigen::ArrayXd> dc, Eigen::Ref<Eigen::ArrayXd> ds) const;
  void RemoveRule(int rule);
  /// ŷ at x, leaving the weights in scratch_.normalized and y_j(x) in rule_outputs_ for the
  /// gradient kernels. @pre rules() ≥ 1.
  double EvaluateInScratch(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  /// After EvaluateInScratch(x) gave ŷ: adds weight · ∂ŷ/∂c and weight · ∂ŷ/∂σ to gc and gs.
  void AddPremiseGradient(const Eigen::Ref<const Eigen::VectorXd>& x, double weight, double yhat,
                          Eigen::ArrayXXd* gc, Eigen::ArrayXXd* gs) const;
  /// Index of the least useful rule old enough to go, or −1.
  int LeastUsefulRule() const;

  // Housekeeping for pruning (eTS+ utility): Σ φ_j since birth, and the birth time.
  Eigen::ArrayXd utility_sum_;
  Eigen::Array<long long, Eigen::Dynamic, 1> born_;
  long long clock_ = 0;
  long long pruned_ = 0;
  std::vector<RuleNames> names_;  // one per rule, in step with rules_

  // Scratch space, sized once, so Predict() and Learn() never allocate.
  mutable Inference scratch_;
  mutable Eigen::ArrayXd rule_outputs_;
  mutable Eigen::ArrayXd gradient_factor_;  // g_j
  mutable Eigen::ArrayXd grad_c_;           // ∂J/∂c_ji for one input
  mutable Eigen::ArrayXd grad_s_;           // ∂J/∂σ_ji for one input
};

}  // namespace odonata::fuzzy
