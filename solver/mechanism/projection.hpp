#pragma once
/// Onto the loops (docs/theory.md §15, eqs. (M8), (M9), (M12)): the projection
/// of q and u in A's metric, and coordinate partitioning's dependent
/// coordinates from the independent ones.
#include <memory>

#include "solver/mechanism/constrained.hpp"

namespace em {

/// Projections onto the loops (theory.md eqs. (M8), (M9)), with scratch
/// preallocated for one model: no allocation per call.
class LoopProjector {
 public:
  explicit LoopProjector(const Model& m);
  struct Result {
    int iterations = 0;      ///< Gauss-Newton steps taken
    bool converged = false;  ///< max |g| <= tol reached
    bool finite = true;      ///< false: a gap was not finite (q is then left as it was at that iterate)
  };
  /// q onto g(q) = 0 by Gauss-Newton in A's metric, at most `iterations`
  /// steps; forms ws's kinematics and A at every iterate.  // q: (nq), u: (nu)
  Result positions(const Model& m, Workspace& ws, double* q, const double* u, double tol, int iterations);
  /// Then u onto G u = 0, the least change in A's metric, at the q that
  /// positions() left (its last G and A).  // u: (nu)
  void velocities(double* u);
  /// The closures at positions()' last iterate (before velocities()).
  const LoopState& loops() const { return loops_; }

 private:
  // dv = A^-1 G^T (G A^-1 G^T)^+ r at the last iterate: by A's tree-sparse
  // factors where the tree's pattern pays (TreeCholesky::pays), else densely.
  void correction(const Eigen::VectorXd& r);
  LoopState loops_;
  ConstrainedSolve solve_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  std::unique_ptr<TreeCholesky> tree_;  // null: the dense path
  Eigen::MatrixXd AinvGt_;     // (nu x m), the dense path's
  Eigen::VectorXd dv_, dq_;    // (nu), (nq)
};

/// Coordinate partitioning (Wehage and Haug; docs/theory.md eq. (M12)): G's
/// columns split into r dependent speeds (the pivots of a column-pivoted QR of
/// G, r its rank at kLoopRankTol) and nu - r independent ones. The dependent
/// coordinates follow from the independent ones: q_d by Newton on g(q) = 0 with
/// q_i held, u_d from G_d u_d = -G_i u_i. The partition is kept while G_d's
/// pivots hold, and chosen anew where its smallest pivot (relative to its
/// largest) falls below 1/kRepartitionRatio of the best partition's.
/// Preallocated for one model: no allocation per call but choose()'s.
inline constexpr double kRepartitionRatio = 10;
/// Where even the best partition's smallest pivot ratio falls below this, G is
/// within 1e-7 of losing rank: a singular position, which coordinate
/// partitioning cannot pass (G_d^-1 amplifies the step's error 1e7 times; on
/// IFToMM A02 the Newton then took another branch, E + W_diss off by 1.5e4 J).
/// The run fails there (`singular`); the projection passes it.
inline constexpr double kSingularPivotRatio = 1e-7;
class CoordinatePartition {
 public:
  explicit CoordinatePartition(const Model& m);
  /// Partition at G (ls.G); returns the rank r.
  int choose(const LoopState& ls);
  bool chosen() const { return !dependent_.empty() || rank_ == 0; }
  /// Whether the partition's pivots have degraded at G (then choose() anew):
  /// its G_d's smallest pivot ratio below the best's / kRepartitionRatio, or G's rank changed.
  bool degraded(const LoopState& ls);
  /// q_d onto g(q) = 0 by Newton with q_i held (at most `iterations` steps;
  /// forms ws's kinematics and `ls` at every iterate), then u_d from G_d u_d =
  /// -G_i u_i at the last iterate.  // q: (nq), u: (nu)
  LoopProjector::Result dependent(const Model& m, Workspace& ws, LoopState& ls, double* q, double* u, double tol, int iterations);
  const std::vector<int>& dependentSpeeds() const { return dependent_; }
  /// The best partition's smallest pivot relative to its largest, at the last choose() or degraded().
  double bestPivotRatio() const { return best_ratio_; }

 private:
  void formGd(const LoopState& ls);  // Gd_ = G's dependent columns, factored
  std::vector<int> dependent_;
  int rank_ = -1;
  double best_ratio_ = 1;
  Eigen::MatrixXd Gd_;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_, qr_d_;
  Eigen::VectorXd step_, dv_, dq_;
};

}  // namespace em
