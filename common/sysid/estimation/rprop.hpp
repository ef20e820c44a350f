#pragma once
// iRprop− (Igel & Hüsken 2000): a step size per parameter that grows while the gradient keeps its
// sign and shrinks when it flips; only the gradient's sign moves a parameter, so parameters of
// very different scales (widths, centres, consequent coefficients) share one optimiser.

#include <algorithm>

#include <Eigen/Core>

namespace odonata::sysid {

class Rprop {
 public:
  static constexpr double kLargestStep = 0.2;  // scaled units
  static constexpr double kSmallestStep = 1e-7;

  /// Fresh steps of `initial` for a rows × cols parameter block.
  void Reset(Eigen::Index rows, Eigen::Index cols, double initial) {
    step_ = Eigen::ArrayXXd::Constant(rows, cols, initial);
    last_ = Eigen::ArrayXXd::Zero(rows, cols);
  }
  bool Matches(Eigen::Index rows, Eigen::Index cols) const {
    return step_.rows() == rows && step_.cols() == cols;
  }
  /// After a rejected step: smaller steps, and no sign memory of the rejected gradient.
  void Backtrack() {
    step_ *= 0.5;
    last_.setZero();
  }
  /// The move for gradient g (same shape as Reset()); updates the steps and the remembered sign.
  Eigen::ArrayXXd Step(const Eigen::ArrayXXd& g) {
    Eigen::ArrayXXd move(g.rows(), g.cols());
    for (Eigen::Index k = 0; k < g.size(); ++k) {
      const double agree = g(k) * last_(k);
      double gk = g(k);
      if (agree > 0.0) {
        step_(k) = std::min(step_(k) * 1.2, kLargestStep);
      } else if (agree < 0.0) {
        step_(k) = std::max(step_(k) * 0.5, kSmallestStep);
        gk = 0.0;  // iRprop−: skip this parameter once after a sign change
      }
      move(k) = gk > 0.0 ? -step_(k) : (gk < 0.0 ? step_(k) : 0.0);
      last_(k) = gk;
    }
    return move;
  }

 private:
  Eigen::ArrayXXd step_, last_;
};

}  // namespace odonata::sysid
