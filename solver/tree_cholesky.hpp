#pragma once
/// A's Cholesky factorization over the tree's own sparsity (docs/theory.md
/// §16, eq. (S1); Featherstone, Rigid Body Dynamics Algorithms, §6.2, his LTDL):
/// A = L^T D L with L unit lower triangular, L_ij != 0 only where speed j is an
/// ancestor of speed i. Eliminating from the leaves up makes no fill: L has
/// A's pattern, and factorization and solves cost O(sum of depths^2) and
/// O(sum of depths), not O(nu^3) and O(nu^2). A wide, shallow tree (a row of
/// four-bars: every crank a root) gets linear cost; a chain gains nothing.
#include <vector>

#include "solver/model.hpp"

namespace em {

class TreeCholesky {
 public:
  explicit TreeCholesky(const Model& m);
  /// Whether the pattern pays over a dense Cholesky: L's entries below the
  /// diagonal at most a quarter of a dense triangle's (kSparseShare).
  static bool pays(const Model& m);
  /// Factor A (formation.hpp's formA: only its tree pattern above the
  /// diagonal is read). False where a pivot is not positive.
  bool factor(const Eigen::MatrixXd& A);
  /// Factor A + diag(extra): the augmented Lagrangian's A + (h/2) C + (h²/4) K
  /// where C and K are the joints' (diagonal).  // extra: (nu)
  bool factor(const Eigen::MatrixXd& A, const Eigen::VectorXd& extra);
  /// The pivots D (the squared pivots of a Cholesky in leaves-first order).
  const Eigen::VectorXd& pivots() const { return D_; }
  /// x <- A^-1 x.  // x: (nu)
  void solveInPlace(double* x) const;
  /// x <- L^-T x on the speeds `support` (ascending, closed under ancestors;
  /// x is zero off it and stays so).
  void solveLtOn(const std::vector<int>& support, double* x) const;
  /// x <- L^-1 x over every speed.
  void solveL(double* x) const;
  /// y = A x over A's tree pattern (its entries above the diagonal, mirrored):
  /// O(sum of depths), where a dense product costs nu^2.  // x, y: (nu), apart
  void multiply(const Eigen::MatrixXd& A, const double* x, double* y) const;
  int size() const { return static_cast<int>(D_.size()); }
  /// The speeds' parent speed (-1 at a root): a body's first speed has its
  /// parent body's last; its others, the one before.
  const std::vector<int>& parents() const { return parent_; }

 private:
  bool eliminate();           // LTDL of the loaded L_, D_ in place
  std::vector<int> parent_;   // (nu)
  std::vector<int> start_;    // (nu + 1) row i's ancestors at [start_[i], start_[i + 1]) of anc_ and L_, nearest first
  std::vector<int> anc_;      // every row's ancestors
  std::vector<double> L_;     // L_ij beside anc_
  Eigen::VectorXd D_;         // (nu)
};

/// The speeds' parent speeds of model m (TreeCholesky::parents).
std::vector<int> speedParents(const Model& m);

}  // namespace em
