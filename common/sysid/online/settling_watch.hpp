#pragma once
// Has the model seen enough? (issue 60 point 3; docs/identifier.md §7.7.) A live judgement, per
// rule and per output, that a pilot flying an identification manoeuvre can act on: settled,
// still learning, or short of excitation — and where to fly for more.
//
// Per output o and rule j it keeps, over the samples learned, the rule's effective samples and
// weighted residuals in the model's scaled units (y in output standard deviations), with φ_kj the
// rule's normalised firing and e_k the one-step residual before y_k was learned:
//   n_j = Σ φ_kj,   σ_j² = Σ φ_kj e_k² / max(n_j − p, 1),   SE_j = σ_j √(p / n_j)
// SE_j is the rule's parameter covariance σ_j² A_j⁻¹ (A_j = Σ φ_kj z_k z_kᵀ, the weighted least
// squares the rule is fitted by) read in the directions its data spans: the standard error of the
// rule's predictions on the data it stands for. Read coefficient by coefficient instead, two lags
// of one signal — nearly equal, so each coefficient is poorly determined alone while their sum is
// sharp — kept well-fitted rules of the DI-MAV's force model "learning" for ever. As PX4's
// attitude autotune watches its RLS covariance fall below a bound, a rule is
//   short of excitation  while n_j < kSamplesPerParameter · p   (p = N + 1 parameters),
//   settled              once SE_j ≤ kSettledStandardError for kSettledSamples samples running,
//   still learning       otherwise.
// Regimes no rule stands for are watched too: each signal's newest lag, in the three thirds
// ("low", "medium", "high") of its scaled range — the declared ranges online — is short while
// fewer than kRegimeSamples samples have visited it. An output is the worst of its rules and
// regimes; the sentence names what to fly. A refit that lands new rules is judged on the samples
// it was fitted on (Rebuild), not from nothing. Judges only: the model never reads it, so
// lockstep runs stay equal to odonata-fit's replay.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "fuzzy/gaussian_rule_base.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {

enum class SettlingState { kShortOfExcitation = 0, kLearning = 1, kSettled = 2 };

/// "short of excitation", "still learning", "settled".
const char* SettlingStateName(SettlingState s);

struct RuleSettling {
  SettlingState state = SettlingState::kShortOfExcitation;
  double samples = 0.0;         ///< n_j, effective samples
  double standard_error = 0.0;  ///< SE_j, output standard deviations (+∞ while A_j is singular)
  std::string regime;           ///< "high u3(k)": where the rule sits
};

struct RegimeSettling {
  std::string signal;               ///< a regressor's name, e.g. "amplitude_rad(k)"
  std::string band;                 ///< "low", "medium" or "high"
  double lower = 0.0, upper = 0.0;  ///< the band in raw units
  int64_t samples = 0;
};

struct OutputSettling {
  SettlingState state = SettlingState::kShortOfExcitation;
  std::vector<RuleSettling> rules;
  std::vector<RegimeSettling> regimes;  ///< three per watched signal
  /// What a pilot reads: "settled", "still learning: rule 2 (high u(k)) SE 0.08", or
  /// "short of excitation: rule 3 (high u(k)): 40 samples, fly more there".
  std::string sentence;
};

class SettlingWatch {
 public:
  /// A rule needs this many effective samples per parameter before it is judged at all.
  static constexpr double kSamplesPerParameter = 2.0;
  /// Output standard deviations (scaled units): the parameters' uncertainty moves the rule's
  /// predictions by at most 5 % of the output's spread (SE_j above).
  static constexpr double kSettledStandardError = 0.05;
  /// The bound must hold this long (1 s at 100 Hz), as PX4's autotune waits before it converges.
  static constexpr int64_t kSettledSamples = 100;
  /// A third of a signal's range counts as visited after this many samples (0.5 s at 100 Hz).
  static constexpr int64_t kRegimeSamples = 50;
  /// The standard errors are solved every this many samples (their cost, not their meaning).
  static constexpr int64_t kCheckEvery = 10;

  /// One learned sample: the raw regressor, the measured outputs and the model's one-step
  /// prediction of them made before learning them. Sizes as the model's.
  void Observe(const NarxModel& model, const Eigen::VectorXd& regressor,
               const Eigen::VectorXd& measured, const Eigen::VectorXd& predicted);
  /// The model's rules were replaced (a refit landed): judged again on `kept`, the samples it
  /// was fitted on (ScheduledRefitter::KeptSeries), as if they had been observed under it. The
  /// regime counts are the flight's and stay.
  void Rebuild(const NarxModel& model, const Series& kept);
  /// Everything forgotten (a model from elsewhere: a RESET, a snapshot, a resume).
  void Clear();

  /// The judgement now, per output of `model` (the model Observe saw).
  std::vector<OutputSettling> Judge(const NarxModel& model) const;
  /// Judge's states alone, without its sentences: cheap enough for every sample.
  std::vector<SettlingState> States(const NarxModel& model) const;
  int64_t observed() const { return observed_; }

 private:
  struct RuleStats {
    double parameters = 1.0;  // p, the consequent's least-squares width
    double samples = 0.0;
    double weighted_squared_error = 0.0;
    double standard_error = 0.0;
    int64_t below_since = -1;  // observed_ when SE first fell (and stayed) below the bound
  };
  struct OutputStats {
    std::vector<RuleStats> rules;
  };
  void Fit(const NarxModel& model);  // sizes the statistics to the model's rule counts
  void Accumulate(const NarxModel& model, const Eigen::VectorXd& regressor,
                  const Eigen::VectorXd& measured, const Eigen::VectorXd& predicted,
                  bool count_regimes);
  void UpdateStandardErrors(const NarxModel& model);
  // One home for the states Judge and States give: a rule's from its statistics; an output's
  // from its rule count, whether a rule or a regime is short, and whether a rule still learns.
  SettlingState RuleState(const RuleStats& s) const;
  const RuleStats& StatsOf(int output, int rule) const;  // of a rule never observed: none
  static SettlingState OutputState(int rules, bool short_of, bool learning);

  std::vector<OutputStats> outputs_;
  int regressor_size_ = -1;           // of the model the statistics are for
  std::vector<int> watched_;          // regressor index of each signal's newest lag
  std::vector<int64_t> band_counts_;  // 3 per watched regressor: samples in low, medium, high
  std::vector<double> band_mid_, band_half_;  // each watched regressor's range, as first scaled
  int64_t observed_ = 0;
  // The firing strengths' scratch, reused per sample and output as the fuzzy layer reuses its own.
  fuzzy::Inference inference_;
};

}  // namespace odonata::sysid
