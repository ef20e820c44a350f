#pragma once
// Ridge least squares over many rows without forming the normal equations (docs/identifier.md
// §6.1).

#include <Eigen/Core>

namespace odonata::fuzzy {

/// Solves min_θ ‖A θ − b‖² + λ s ‖θ‖², s = mean_j ‖A_·j‖² (so λ is relative to the design's
/// scale), for A fed in row blocks. Each block is folded into the R factor of a Householder QR of
/// [A b], so memory is O((block + n) n) for any number of rows and the condition number is never
/// squared as AᵀA would square it. The final n × n problem is solved by a complete orthogonal
/// decomposition: with λ = 0 a rank-deficient A gets the minimum-norm solution, and the training
/// residual never grows as λ shrinks.
class BlockwiseLeastSquares {
 public:
  /// @pre columns ≥ 1.
  explicit BlockwiseLeastSquares(Eigen::Index columns);

  /// Adds rows: a is rows × columns, b has rows entries.
  void AddRows(const Eigen::Ref<const Eigen::MatrixXd>& a,
               const Eigen::Ref<const Eigen::VectorXd>& b);
  /// Adds rows ‖P θ‖² that regularise rather than carry data (zero targets): they are not rows of
  /// A, so the ridge's scale s stays the data's however large P is.
  void AddPenalty(const Eigen::Ref<const Eigen::MatrixXd>& p);

  /// θ for relative ridge λ ≥ 0; zeros before any row was added.
  Eigen::VectorXd Solve(double relative_ridge) const;

  Eigen::Index columns() const { return columns_; }
  Eigen::Index rows_added() const { return rows_added_; }

 private:
  Eigen::Index columns_;
  Eigen::Index rows_added_ = 0;
  Eigen::MatrixXd r_;  // upper-trapezoidal R of [A b], `filled_` rows in use
  Eigen::Index filled_ = 0;
  Eigen::VectorXd column_squares_;  // Σ_k A_kj², for the ridge's scale
  void Fold(const Eigen::Ref<const Eigen::MatrixXd>& a, const Eigen::Ref<const Eigen::VectorXd>& b);
};

}  // namespace odonata::fuzzy
