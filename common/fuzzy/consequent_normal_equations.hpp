#pragma once
// The consequents' ridge least squares (FuzzyModel::RefineConsequents) as normal equations
// gathered rule block by rule block (docs/identifier.md §6.1): a design row is φ ⊗ z, and a run
// of neighbouring samples fires only a few of a large rule base's rules.

#include <vector>

#include <Eigen/Core>

namespace odonata::fuzzy {

/// Whether the parameters are each rule's own (θ_j) or one shared part plus each rule's deviation
/// (θ_j = g + δ_j, whose deviations alone take the deviation ridge).
enum class SharedPart { kNone, kGlobal };

/// Solves min_θ ‖Φ θ − y‖² + λ s ‖θ‖² (+ μ s_δ ‖δ‖² with a shared part), Φ's row k being
/// [φ_k1 z_k, …, φ_kR z_k] (with a shared part, [z_k, φ_k1 z_k, …]), s the mean squared column
/// norm of Φ and s_δ that of its deviation columns (so both ridges are relative to the data).
///
/// Why normal equations rather than a blockwise QR of Φ: the QR costs 2 m² flops a row for
/// m = R · width parameters whatever fires. Here rows are taken kTileRows at a time, and
/// only the rules that fire within a tile (normalised firing above kNegligibleFiring at one of its
/// rows — 1e-12 of firings that sum to 1, two orders below the relative ridge 1e-10) enter its
/// Gram update, computed as one symmetric rank-k product. The squared condition number is bounded
/// by the ridge (the solve is a Cholesky of ΦᵀΦ + λ s I); without a ridge, or if the Cholesky
/// fails, a complete orthogonal decomposition of the Gram matrix gives the minimum-norm solution.
class ConsequentNormalEquations {
 public:
  static constexpr double kNegligibleFiring = 1e-12;
  static constexpr Eigen::Index kTileRows = 64;

  /// @pre rules ≥ 1, width ≥ 1.
  ConsequentNormalEquations(int rules, int width, SharedPart shared);

  /// Adds rows: `phi` the normalised firings (rows × rules), `z` the consequent's regressor
  /// (rows × width), `y` the targets.
  /// @throws std::invalid_argument for mismatched shapes.
  void AddRows(const Eigen::Ref<const Eigen::ArrayXXd>& phi,
               const Eigen::Ref<const Eigen::MatrixXd>& z,
               const Eigen::Ref<const Eigen::VectorXd>& y);

  /// Every rule's parameters (rules × width, rule-major; with a shared part, g + δ_j), for the
  /// relative ridge λ ≥ 0 on every column and μ ≥ 0 on the deviations; zeros before any row.
  /// `residual_squares`, if given, receives ‖Φ θ − y‖² from the Gram matrix (yᵀy − 2 θᵀΦᵀy +
  /// θᵀΦᵀΦθ): the training loss without another pass over the rows, to about 1e-10 of it at a
  /// one-step FIT of 99.9 %.
  Eigen::VectorXd Solve(double relative_ridge, double deviation_ridge = 0.0,
                        double* residual_squares = nullptr) const;

  long rows_added() const { return rows_added_; }
  Eigen::Index columns() const { return gram_.cols(); }

 private:
  int rules_, width_;
  Eigen::Index offset_;          // the first rule block's column: 0, or width with a shared part
  Eigen::MatrixXd gram_;         // ΦᵀΦ, upper triangle kept
  Eigen::VectorXd moment_;       // Φᵀy
  double target_squares_ = 0.0;  // yᵀy
  long rows_added_ = 0;
  // Scratch, kept between tiles: the firing rules' columns, the tile's compact design and Gram.
  std::vector<int> firing_rules_;
  std::vector<Eigen::Index> columns_of_tile_;
  Eigen::MatrixXd tile_design_, tile_gram_;

  void AddTile(const Eigen::Ref<const Eigen::ArrayXXd>& phi,
               const Eigen::Ref<const Eigen::MatrixXd>& z,
               const Eigen::Ref<const Eigen::VectorXd>& y);
};

}  // namespace odonata::fuzzy
