#include "fuzzy/consequent_normal_equations.hpp"

#include <algorithm>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/QR>

namespace odonata::fuzzy {

ConsequentNormalEquations::ConsequentNormalEquations(int rules, int width, SharedPart shared)
    : rules_(rules), width_(width), offset_(shared == SharedPart::kGlobal ? width : 0) {
  if (rules < 1 || width < 1)
    throw std::invalid_argument("least squares needs at least one rule and one column");
  const Eigen::Index m = offset_ + Eigen::Index{rules} * width;
  gram_ = Eigen::MatrixXd::Zero(m, m);
  moment_ = Eigen::VectorXd::Zero(m);
}

void ConsequentNormalEquations::AddRows(const Eigen::Ref<const Eigen::ArrayXXd>& phi,
                                        const Eigen::Ref<const Eigen::MatrixXd>& z,
                                        const Eigen::Ref<const Eigen::VectorXd>& y) {
  if (phi.cols() != rules_ || z.cols() != width_ || phi.rows() != z.rows() ||
      phi.rows() != y.size())
    throw std::invalid_argument("least squares rows have the wrong shape");
  for (Eigen::Index start = 0; start < y.size(); start += kTileRows) {
    const Eigen::Index rows = std::min(kTileRows, y.size() - start);
    AddTile(phi.middleRows(start, rows), z.middleRows(start, rows), y.segment(start, rows));
  }
  rows_added_ += y.size();
  target_squares_ += y.squaredNorm();
}

void ConsequentNormalEquations::AddTile(const Eigen::Ref<const Eigen::ArrayXXd>& phi,
                                        const Eigen::Ref<const Eigen::MatrixXd>& z,
                                        const Eigen::Ref<const Eigen::VectorXd>& y) {
  const Eigen::Index rows = y.size();
  columns_of_tile_.clear();
  for (Eigen::Index c = 0; c < offset_; ++c) columns_of_tile_.push_back(c);
  std::vector<int>& firing = firing_rules_;
  firing.clear();
  for (int j = 0; j < rules_; ++j)
    if (phi.col(j).maxCoeff() > kNegligibleFiring) firing.push_back(j);
  for (const int j : firing)
    for (int c = 0; c < width_; ++c)
      columns_of_tile_.push_back(offset_ + Eigen::Index{j} * width_ + c);
  const auto n = static_cast<Eigen::Index>(columns_of_tile_.size());
  tile_design_.resize(rows, n);
  if (offset_ > 0) tile_design_.leftCols(offset_) = z;
  for (std::size_t f = 0; f < firing.size(); ++f)
    tile_design_.middleCols(offset_ + static_cast<Eigen::Index>(f) * width_, width_) =
        z.array().colwise() * phi.col(firing[f]);
  tile_gram_.setZero(n, n);
  tile_gram_.selfadjointView<Eigen::Upper>().rankUpdate(tile_design_.transpose());
  const Eigen::VectorXd tile_moment = tile_design_.transpose() * y;
  // Columns ascend, so the tile's upper triangle lands in the Gram matrix's.
  for (Eigen::Index q = 0; q < n; ++q) {
    const Eigen::Index gq = columns_of_tile_[static_cast<std::size_t>(q)];
    moment_(gq) += tile_moment(q);
    for (Eigen::Index p = 0; p <= q; ++p)
      gram_(columns_of_tile_[static_cast<std::size_t>(p)], gq) += tile_gram_(p, q);
  }
}

Eigen::VectorXd ConsequentNormalEquations::Solve(double relative_ridge, double deviation_ridge,
                                                 double* residual_squares) const {
  const Eigen::Index m = gram_.cols();
  const Eigen::Index rule_columns = m - offset_;
  if (rows_added_ == 0) {
    if (residual_squares) *residual_squares = 0.0;
    return Eigen::VectorXd::Zero(rule_columns);
  }
  Eigen::MatrixXd a = gram_.selfadjointView<Eigen::Upper>();
  const Eigen::VectorXd squares = gram_.diagonal();  // each column's squared norm
  if (offset_ > 0 && deviation_ridge > 0.0)
    a.diagonal().tail(rule_columns).array() += deviation_ridge * squares.tail(rule_columns).mean();
  const double ridge = std::max(0.0, relative_ridge) * squares.mean();
  a.diagonal().array() += ridge;
  Eigen::VectorXd theta;
  if (ridge > 0.0) {
    const Eigen::LLT<Eigen::MatrixXd> llt(a);
    if (llt.info() == Eigen::Success) theta = llt.solve(moment_);
  }
  if (theta.size() == 0 || !theta.allFinite()) {
    // The Gram matrix holds rounding of about ε ‖ΦᵀΦ‖: pivots below 1e-12 of the largest are
    // that rounding, not data (a singular value of Φ below 1e-6 of its largest).
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
    cod.setThreshold(1e-12);
    theta = cod.compute(a).solve(moment_);
  }
  if (residual_squares) {
    const double fitted = theta.dot(gram_.selfadjointView<Eigen::Upper>() * theta);
    *residual_squares = std::max(0.0, target_squares_ - 2.0 * theta.dot(moment_) + fitted);
  }
  if (offset_ == 0) return theta;
  Eigen::VectorXd own(rule_columns);
  for (int j = 0; j < rules_; ++j)
    own.segment(Eigen::Index{j} * width_, width_) =
        theta.head(offset_) + theta.segment(offset_ + Eigen::Index{j} * width_, width_);
  return own;
}

}  // namespace odonata::fuzzy
