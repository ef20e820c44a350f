#pragma once
// The THEN part of the rules, as a strategy behind one rule base (docs/identifier.md §1 and §2).

#include <memory>
#include <string>

#include <Eigen/Core>

namespace odonata::fuzzy {

/// Which consequent a model uses. Chosen by enum, not by string, except at the CLI/JSON edge.
enum class ConsequentKind {
  kSingleton,  ///< the paper's Mamdani singletons b_j, centre-average defuzzification; readable.
  kLinear,     ///< first-order Takagi–Sugeno y_j = a_j0 + a_jᵀx; accurate.
};

const char* ToString(ConsequentKind kind);
/// @throws std::invalid_argument for anything but "singleton" or "linear".
ConsequentKind ConsequentKindFromString(const std::string& name);

/// Rule consequents. All values are in the model's scaled units. The model output is
/// ŷ = Σ_j φ_j y_j(x), so every strategy only has to say what y_j(x) is and how it learns.
struct ConsequentState;  // fuzzy_model_state.hpp

class Consequent {
 public:
  virtual ~Consequent() = default;
  virtual ConsequentKind kind() const = 0;
  virtual std::unique_ptr<Consequent> Clone() const = 0;

  /// Writes y_j(x) for the first `rules` rules into `out` (sized by the caller).
  virtual void RuleOutputs(const Eigen::Ref<const Eigen::VectorXd>& x, int rules,
                           Eigen::ArrayXd* out) const = 0;

  /// Initialises consequent `rule` (== current count) for a rule created at x whose target is y.
  /// `phi_existing` holds the normalised weights of the rules that existed before it.
  virtual void AddRule(const Eigen::Ref<const Eigen::VectorXd>& x, double target,
                       const Eigen::Ref<const Eigen::ArrayXd>& phi_existing) = 0;

  /// Removes consequent `rule`; later rules move up one place. @pre 0 ≤ rule < rules().
  virtual void RemoveRule(int rule) = 0;
  /// Sets the forgetting factor λ ∈ (0, 1] of a recursive learner (1 never forgets). Learners
  /// that track by construction (NLMS) ignore it.
  virtual void SetForgetting(double /*lambda*/) {}

  /// One online learning step given the weights φ, the output error e = ŷ − y and target y.
  virtual void Update(const Eigen::Ref<const Eigen::VectorXd>& x,
                      const Eigen::Ref<const Eigen::ArrayXd>& phi, double error, double target) = 0;

  /// ∂J/∂(consequent parameters) for J = ½e², flattened as Parameters() orders them.
  virtual Eigen::VectorXd Gradient(const Eigen::Ref<const Eigen::VectorXd>& x,
                                   const Eigen::Ref<const Eigen::ArrayXd>& phi,
                                   double error) const = 0;
  /// Adds Σ_j φ_j ∂y_j/∂x to `dydx` (the rule outputs' own slope; the firing's part is the
  /// model's): what a free run feeds back through its lagged predictions.
  virtual void AddInputGradient(const Eigen::Ref<const Eigen::ArrayXd>& phi,
                                Eigen::Ref<Eigen::VectorXd> dydx) const = 0;
  /// All trainable consequent parameters of the active rules, flattened (for checks and I/O).
  virtual Eigen::VectorXd Parameters() const = 0;
  virtual void SetParameters(const Eigen::Ref<const Eigen::VectorXd>& p) = 0;

  /// Number of regressors per rule in the global least-squares problem (1 or N + 1), and the
  /// regressor itself; the model builds Φ from these to solve all consequents at once (ANFIS).
  virtual int LeastSquaresWidth() const = 0;
  virtual void LeastSquaresRow(const Eigen::Ref<const Eigen::VectorXd>& x,
                               Eigen::Ref<Eigen::VectorXd> z) const = 0;
  /// Sets the consequents from a global least-squares solution (rule-major blocks).
  virtual void SetFromLeastSquares(const Eigen::Ref<const Eigen::VectorXd>& theta) = 0;

  virtual int rules() const = 0;
  /// Everything needed to rebuild it (fuzzy_model_state.hpp).
  virtual ConsequentState State() const = 0;
};

/// Creates an empty consequent for `inputs` regressors with room for `capacity` rules; `forgetting`
/// is the recursive learner's λ (linear consequents).
std::unique_ptr<Consequent> MakeConsequent(ConsequentKind kind, int inputs, int capacity,
                                           double forgetting = 1.0);
/// The largest magnitudes a model read from a file or a snapshot may hold (ConsequentFromState,
/// FuzzyModel::FromState): finite but absurd values — a covariance of 1e300, a coefficient of
/// 1e300 — made every prediction NaN from the fourth sample on. The learners never come near
/// them: in scaled units the outputs are of order 1, the RLS covariance's trace is capped at
/// initial_covariance · (inputs + 1) (10³ by default), and a premise a .fis leaves out is 10³ wide.
inline constexpr double kMaxCoefficient = 1e9;     ///< a consequent's coefficient, scaled units
inline constexpr double kMaxCovariance = 1e12;     ///< an RLS covariance entry or P₀
inline constexpr double kMaxLearnerSetting = 1e6;  ///< NLMS rate and regulariser
inline constexpr double kMaxRuleExtent = 1e6;      ///< a centre's magnitude, a width, scaled units

/// Rebuilds a consequent from its State().
/// @throws std::runtime_error naming what is wrong (counts, sizes, non-finite or absurd values).
std::unique_ptr<Consequent> ConsequentFromState(const ConsequentState& state, int inputs,
                                                int capacity);

}  // namespace odonata::fuzzy
