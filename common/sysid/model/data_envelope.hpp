#pragma once
// Outside the data, the global linear model (docs/identifier.md §7.3). A Takagi–Sugeno model
// predicts, far from every rule, with the nearest rule's local model followed out of the range
// it was fitted on; a K-step or free-run prediction that leaves the data (another manoeuvre,
// another flight) then feeds that extrapolation back as a lag and can run away where a straight
// line would not. The envelope holds, per output, the global linear model (least squares on the
// model's training rows: ARX on the same regressor) and how far from its nearest rule, in rule
// widths, the farthest training row lay, and the box the training rows span (each regressor's
// least and greatest value). A prediction farther from its nearest rule than that radius, or
// outside the box, blends smoothly into the linear model; inside both the fuzzy prediction is
// unchanged, so training rows and data like them are predicted exactly as before. Both are
// needed: wide rules (a width near the data's whole range) leave a regressor far outside its
// range within a width or two of a rule (trained on half the Narendra plant's input range, the
// model gave −1227 % one step on all of it, ARX 28 %), and a box cannot see a K-step prediction
// that leaves the data's thin diagonal (y(k−1) ≈ y(k−2)) while staying inside it.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace odonata::fuzzy {
class FuzzyModel;
}

namespace odonata::sysid {

/// One output's envelope, in the model's scaled units.
struct OutputEnvelope {
  /// The global linear model: intercept first, then one coefficient per regressor.
  Eigen::VectorXd linear;
  /// The largest distance from a training row to its nearest rule (Mahalanobis, in widths).
  double radius_widths = 0.0;
};

struct DataEnvelope {
  /// Past the radius, the blend reaches the linear model over this many widths (a smoothstep):
  /// one width, so a prediction one rule width beyond anything trained on is the linear model's.
  static constexpr double kBlendWidths = 1.0;

  /// Outside the box, the blend reaches the linear model this share of a regressor's training
  /// span beyond it. A quarter: the Narendra plant trained on half its input range then gives
  /// 32.0 % one step on all of it (ARX 27.7 %); with a tenth 30.7 %, with half 14.2 %. The
  /// tail-sitter's rates leave their training range on the selection flight and the rules
  /// extrapolate well there: 0.5 s ahead the pitch rate gave 47.5 % without a box, 44.3 % with
  /// a quarter, 39.7 % with a tenth (training and selection flights only).
  static constexpr double kBoxBlendSpan = 0.25;

  std::vector<OutputEnvelope> outputs;  ///< empty: no envelope (the fuzzy model everywhere)
  /// The box of the training rows (scaled regressors): each regressor's least and greatest value.
  Eigen::VectorXd lower, upper;

  bool any() const { return !outputs.empty(); }
  /// The envelope of `models` (one per output) over the scaled training rows xs (rows ×
  /// regressors) and targets ys (rows × outputs). None when every model has at most one rule
  /// (a one-rule model is linear already) or there are fewer rows than parameters.
  static DataEnvelope Fit(const std::vector<fuzzy::FuzzyModel>& models,
                          const Eigen::Ref<const Eigen::MatrixXd>& xs,
                          const Eigen::Ref<const Eigen::MatrixXd>& ys);
  /// The share of the linear model for output o at scaled regressor x, `distance_widths` from
  /// its nearest rule: 0 within the radius and the box, 1 from kBlendWidths beyond the radius or
  /// kBoxBlendSpan beyond the box, a smoothstep between; the larger of the two.
  double LinearShare(int output, const Eigen::Ref<const Eigen::VectorXd>& x,
                     double distance_widths) const;
  /// The blended prediction (scaled units) of output o at scaled regressor x, whose fuzzy
  /// prediction is `fuzzy`, with the linear model's share `share` (LinearShare).
  double Blend(int output, const Eigen::Ref<const Eigen::VectorXd>& x, double fuzzy,
               double share) const;
  /// Wrong sizes, a non-finite coefficient or radius; empty when fine.
  std::string Problems(int outputs, int regressors) const;
  nlohmann::json ToJson() const;
  static DataEnvelope FromJson(const nlohmann::json& j);
};

}  // namespace odonata::sysid
