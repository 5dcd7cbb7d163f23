#pragma once
/// The constrained accelerations of a mechanism (docs/theory.md §15, eqs.
/// (M7), (M11)): the multipliers by G A^-1 G^T, or Udwadia-Kalaba's M (G M)^+,
/// and a mechanism's equations at one state.
#include <Eigen/QR>

#include "solver/mechanism/loops.hpp"
#include "solver/tree_cholesky.hpp"

namespace em {

/// The rank threshold of G A^-1 G^T, relative to its largest pivot: rows
/// beyond the rank are redundant (a planar mechanism closed by balls, Bricard).
inline constexpr double kLoopRankTol = 1e-10;
/// The same decision for G M (M M^T = A^-1), whose singular values are the
/// square roots of G A^-1 G^T's: sqrt(1e-10).
inline constexpr double kLoopRankTolUK = 1e-5;

/// How the multipliers are had (docs/theory.md §15): u' = a + A^-1 G^T lambda,
/// (G A^-1 G^T) lambda = -c - 2 alpha G u - beta^2 g - G a, a = A^-1 B, solved
/// by a complete orthogonal decomposition (rank-revealing; least-norm lambda
/// on redundant rows). Preallocated for one model: no allocation per call.
class ConstrainedSolve {
 public:
  explicit ConstrainedSolve(const Model& m);
  /// u' in place (the tree's a on entry), lambda, given AinvGt = A^-1 G^T.
  /// Returns the rank of G A^-1 G^T.
  int solve(const LoopState& ls, const Eigen::MatrixXd& AinvGt, double alpha, double beta, Eigen::Ref<Eigen::VectorXd> udot);
  /// Udwadia-Kalaba: u' += M (G M)^+ (b - G a), b = -c - 2 alpha G u - beta^2 g,
  /// M M^T = A^-1 (docs/theory.md eq. (M11)). Rank from G M's complete orthogonal
  /// decomposition at kLoopRankTolUK. Returns that rank; lambda() is not formed.
  int solveUdwadiaKalaba(const LoopState& ls, const Eigen::MatrixXd& M, double alpha, double beta,
                         Eigen::Ref<Eigen::VectorXd> udot);
  /// out = A^-1 G^T (G A^-1 G^T)^+ r: the least change in A's metric that
  /// takes G's rows by r (a projection's step).  // r: (m), out: (nu)
  void correction(const LoopState& ls, const Eigen::MatrixXd& AinvGt, const Eigen::VectorXd& r, Eigen::VectorXd& out);
  /// The same two, at linear cost, from A's tree-sparse factors (docs/theory.md
  /// §16, eqs. (S1)-(S3)): Y = L^-T G^T on each loop's speeds, G A^-1 G^T =
  /// Y^T D^-1 Y over the pairs of loops that share speeds, factored by an
  /// envelope LDL^T whose pivots below kLoopRankTol of the largest diagonal
  /// drop their rows (redundant: lambda 0 there, which leaves u' as the least-norm
  /// lambda does on consistent rows; the lambda itself is then not the least-norm one).
  int solve(const LoopState& ls, const TreeCholesky& A, double alpha, double beta, Eigen::Ref<Eigen::VectorXd> udot);
  void correction(const LoopState& ls, const TreeCholesky& A, const Eigen::VectorXd& r, Eigen::VectorXd& out);
  /// The augmented Lagrangian's penalized projection at linear cost (docs/theory.md
  /// §16, eq. (S4)): with W = I / shift,
  /// (A + G^T W G)^-1 G^T W r = A^-1 G^T (shift I + G A^-1 G^T)^-1 r (Woodbury).
  /// factorPenalty factors shift I + G A^-1 G^T (positive definite for shift > 0:
  /// no row dropped); penaltySolve then gives out = the right side at r.  // r: (m), out: (nu)
  void factorPenalty(const LoopState& ls, const TreeCholesky& A, double shift);
  void penaltySolve(const TreeCholesky& A, const Eigen::VectorXd& r, Eigen::VectorXd& out);
  /// The rank of G A^-1 G^T by the sparse path's drop rule; nothing solved.
  int rankOf(const LoopState& ls, const TreeCholesky& A);
  /// out = G x and out += G^T v over each row's loop speeds, G's only nonzero
  /// columns: linear cost, where the dense products cost rows x nu.  // x, out: (nu) or (m)
  void timesG(const LoopState& ls, const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> out) const;
  void addTimesGt(const LoopState& ls, const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Ref<Eigen::VectorXd> out) const;
  const Eigen::VectorXd& lambda() const { return lambda_; }
  int rank() const { return rank_; }

 private:
  // r_ = b - G a, b = -c - 2 alpha G u - beta^2 g, from Ga_ = G a (formed densely or on the loops' speeds).
  void residual(const LoopState& ls, double alpha, double beta);
  // The tree-sparse path: G A^-1 G^T's envelope factored (eq. (S2)); lambda_ = its solution at r.
  void factorSparse(const LoopState& ls, const TreeCholesky& A, double shift = 0);  // shift > 0: S + shift I, none dropped
  void solveSparse(const Eigen::VectorXd& r);
  void addInverseAGt(const TreeCholesky& A, double* out);  // out += A^-1 G^T lambda_ (eq. (S3))
  const Model& m_;
  Eigen::MatrixXd S_, GM_;
  Eigen::VectorXd r_, lambda_, w_, Ga_;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_, cod_gm_;
  int rank_ = 0;
  // The sparse path's pattern, fixed by the model: each row's loop, each loop's
  // first row, the pairs of loops (a >= b) that share speeds and those speeds,
  // and each row's first column in the envelope of G A^-1 G^T.
  struct SharedSpeeds {
    int a, b;
    std::vector<int> speeds;
  };
  std::vector<int> row_loop_, loop_row_, first_;
  std::vector<SharedSpeeds> pairs_;
  Eigen::MatrixXd Y_;                                                   // (nu x m) L^-T G^T, on each row's loop speeds
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> E_;  // (m x m) the envelope: S, then L below its diagonal
  Eigen::VectorXd d_, v_;                                               // (m) pivots (0: dropped), (nu) scratch
};

/// A mechanism's equations at one state (theory.md eq. (M7), solved by
/// Cholesky): the closures (g, G, c), the rank of G A^-1 G^T, the multipliers
/// lambda (the force on body a's point, and for a direction row the moment
/// along e x f; the least-norm one on redundant rows) and the constrained u'.
struct ConstrainedEquations {
  explicit ConstrainedEquations(const Model& m) : loops(m) {}
  LoopState loops;
  Eigen::VectorXd udot, lambda;
  int rank = 0;
};
/// From a Workspace whose A and B are formed at (q, u) (formEquations).  // u: (nu)
ConstrainedEquations constrainedAt(const Model& m, const Workspace& ws, const double* u);

/// tr.loop_samples and tr.lambda_names at every sample of a run on `m` (a
/// model with loops; nothing otherwise): the violation by our g(q) and G u,
/// and (M7)'s lambda at the sampled state, whoever made the run (an engine's
/// samples are measured the same way). Bookkeeping after the run: it allocates.
void recordLoopSamples(const Model& m, Trajectory& tr);

}  // namespace em
