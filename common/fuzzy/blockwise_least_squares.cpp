#include "fuzzy/blockwise_least_squares.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/QR>

namespace odonata::fuzzy {

BlockwiseLeastSquares::BlockwiseLeastSquares(Eigen::Index columns)
    : columns_(columns),
      r_(Eigen::MatrixXd::Zero(columns + 1, columns + 1)),
      column_squares_(Eigen::VectorXd::Zero(columns)) {
  if (columns < 1) throw std::invalid_argument("least squares needs at least one column");
}

void BlockwiseLeastSquares::AddRows(const Eigen::Ref<const Eigen::MatrixXd>& a,
                                    const Eigen::Ref<const Eigen::VectorXd>& b) {
  if (a.cols() != columns_ || a.rows() != b.size())
    throw std::invalid_argument("least squares block has the wrong shape");
  if (a.rows() == 0) return;
  column_squares_ += a.colwise().squaredNorm().transpose();
  rows_added_ += a.rows();
  Fold(a, b);
}

void BlockwiseLeastSquares::AddPenalty(const Eigen::Ref<const Eigen::MatrixXd>& p) {
  if (p.cols() != columns_)
    throw std::invalid_argument("least squares penalty has the wrong shape");
  if (p.rows() == 0) return;
  Fold(p, Eigen::VectorXd::Zero(p.rows()));
}

void BlockwiseLeastSquares::Fold(const Eigen::Ref<const Eigen::MatrixXd>& a,
                                 const Eigen::Ref<const Eigen::VectorXd>& b) {
  const Eigen::Index n1 = columns_ + 1;
  Eigen::MatrixXd stack(filled_ + a.rows(), n1);
  stack.topRows(filled_) = r_.topRows(filled_);
  stack.bottomLeftCorner(a.rows(), columns_) = a;
  stack.bottomRightCorner(a.rows(), 1) = b;
  // Only R is kept: Qᵀ [A b] = [R_A q; 0 ρ], and R_A θ = q is the least-squares system.
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(stack);
  filled_ = std::min(stack.rows(), n1);
  r_.topRows(filled_) = qr.matrixQR().topRows(filled_).triangularView<Eigen::Upper>();
}

Eigen::VectorXd BlockwiseLeastSquares::Solve(double relative_ridge) const {
  if (filled_ == 0) return Eigen::VectorXd::Zero(columns_);
  const Eigen::Index k = std::min(filled_, columns_);
  const double scale = column_squares_.mean();
  const double root = std::sqrt(std::max(0.0, relative_ridge) * scale);
  const Eigen::Index extra = root > 0.0 ? columns_ : 0;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(k + extra, columns_);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(k + extra);
  m.topRows(k) = r_.topLeftCorner(k, columns_);
  rhs.head(k) = r_.col(columns_).head(k);
  if (extra > 0) m.bottomRows(extra).diagonal().setConstant(root);
  return Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(m).solve(rhs);
}

}  // namespace odonata::fuzzy
