#pragma once
/// What makes a tree a mechanism (docs/theory.md §15): the closures' g(q),
/// their Jacobian G (in u, so that g' = G u) and the velocity-product part
/// of g'' (g'' = G u' + c), the point spring-dampers' and the drives'
/// generalized forces and energies, and the constrained accelerations.
/// Everything here reads a Workspace whose kinematics are formed
/// (formKinematics: R, omega, P, P', the joint points and their velocities).
#include <string>

#include <Eigen/QR>

#include "solver/formation.hpp"
#include "solver/method_options.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// One row per formulation (solver/method_options.hpp's Formulation): its
/// name (--formulation) and what it does.
struct FormulationInfo {
  Formulation id;
  const char* name;
  const char* summary;
};
const std::vector<FormulationInfo>& formulationTable();
const char* formulationName(Formulation f);
/// The formulation named `name`, or false.
bool findFormulation(const std::string& name, Formulation& out);

/// A point of a body (or of the ground) at the formed kinematics: world
/// position and velocity.
struct PointMotion {
  Vec3 x = Vec3::Zero(), v = Vec3::Zero();
};
PointMotion pointMotion(const Workspace& ws, const Attachment& p);

/// rows += sign * J, J (3 x nu) the Jacobian of the velocity of world point x
/// moving with `body` (x' = J u): over the body's path to the ground, a slide
/// column p_k, a turning column p_k x (x - o_k) (theory.md eq. (M2)).
void addPointJacobian(const Model& m, const Workspace& ws, int body, const Vec3& x, double sign,
                      Eigen::Ref<Eigen::MatrixXd> rows);
/// rows += sign * J_w, J_w (3 x nu) the Jacobian of the body's angular velocity.
void addAngularJacobian(const Model& m, const Workspace& ws, int body, double sign, Eigen::Ref<Eigen::MatrixXd> rows);
/// x'' at u' = 0 for the world point x moving with `body` at velocity xdot: J' u
/// (theory.md eq. (M3)).  // u: (nu)
Vec3 pointBias(const Model& m, const Workspace& ws, const double* u, int body, const Vec3& x, const Vec3& xdot);
/// omega' at u' = 0: J_w' u.
Vec3 angularBias(const Model& m, const Workspace& ws, const double* u, int body);

/// The closures at one state: g (m), G (m x nu), G u, and c = G' u, so that
/// g'' = G u' + c (theory.md eqs. (M1)-(M4)); m = Model::loop_rows.
struct LoopState {
  explicit LoopState(const Model& m);
  Eigen::VectorXd g, Gu, c;
  Eigen::MatrixXd G;
  Eigen::Matrix3Xd Jw;  ///< scratch: an angular Jacobian (3 x nu)
  /// Per loop, how far its directions are turned from where the closure holds
  /// them (rad; 0 for a ball): a hinge's angle between axis_a and axis_b, a
  /// weld's angle of R_b against R_a rel (eq. (M4b)). The direction rows g
  /// vanish also at turns that are not the closure's (a weld's frame turned
  /// 120 degrees about its diagonal, a hinge's axes opposed); this does not.
  std::vector<double> turn;
  /// The largest |g| over the ball rows (m), the largest turn (rad), and the
  /// largest |G u| over the ball and the axis rows (m/s, rad/s): what a
  /// report calls the violation.
  double position_m = 0, position_rad = 0, velocity_m = 0, velocity_rad = 0;
};
/// g, G, G u and c at the formed kinematics.  // u: (nu)
void formLoops(const Model& m, const Workspace& ws, const double* u, LoopState& ls);

/// Q += the joint springs', the drives' and the point spring-dampers'
/// generalized forces (theory.md eq. (M5)).  // q: (nq), u, Q: (nu)
void addAppliedForces(const Model& m, const Workspace& ws, const double* q, const double* u, Eigen::VectorXd& Q);
/// Q += the drives' and the point spring-dampers' generalized forces alone
/// (what a tree's u' from outside lacks: a plugin's tau).  // Q: (nu)
void addMechanismForces(const Model& m, const Workspace& ws, Eigen::VectorXd& Q);
/// The force on a's point of point spring-damper `s` whose points are at pa
/// and pb, moving at va and vb (world): tension k (l - length) + c l' along
/// the line from a's point to b's; -f acts on b's; zero where the points
/// coincide (io keeps them apart at the start). The engines that apply point
/// springs as forces (ODE, Bullet, DART) take it from their own states.
Vec3 pointSpringForce(const PointSpring& s, const Vec3& pa, const Vec3& va, const Vec3& pb, const Vec3& vb);
/// Potential of the point springs, sum of k (l - length)^2 / 2.
double pointSpringPotential(const Model& m, const Workspace& ws);
/// dW_diss/dt: the power the joint and point dampers dissipate minus the
/// power the drives put in (theory.md eq. (M6)); E + W_diss is conserved.
double nonConservativePower(const Model& m, const Workspace& ws, const double* u);

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
  const Eigen::VectorXd& lambda() const { return lambda_; }
  int rank() const { return rank_; }

 private:
  void residual(const LoopState& ls, double alpha, double beta, const Eigen::Ref<const Eigen::VectorXd>& a);
  Eigen::MatrixXd S_, GM_;
  Eigen::VectorXd r_, lambda_, w_;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_, cod_gm_;
  int rank_ = 0;
};

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
  LoopState loops_;
  ConstrainedSolve solve_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::MatrixXd AinvGt_;     // (nu x m)
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

/// s's largest violations grow by ls's (what a report calls the violation).
void recordViolation(const LoopState& ls, LoopStats& s);

/// The loops' violation at a state another engine reached (its samples), by
/// our g(q) and G u: LoopStats' largest values grow; rank is not touched.
class LoopMeter {
 public:
  explicit LoopMeter(const Model& m) : m_(m), ws_(m), loops_(m) {}
  void record(const double* q, const double* u, LoopStats& s);  // q: (nq), u: (nu)

 private:
  const Model& m_;
  Workspace ws_;
  LoopState loops_;
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

/// Set each weld's relative orientation from the model's initial state
/// (Loop::rel); a model without welds is left as it is.
void finishMechanism(Model& m);

/// What assembling a start did (the scene's simulate.assemble, --assemble):
/// the gaps it found and how far it moved q0 and u0.
struct Assembly {
  double gap = 0, velocity_gap = 0;  ///< max |g| (m or rad) and max |G u| (m/s or rad/s) before
  double moved_q = 0, moved_u = 0;   ///< max |q - q0| (rad or m; quaternion parts), max |u - u0|
  int iterations = 0;                ///< Gauss-Newton steps
  bool converged = false;            ///< max |g| <= tol reached (else the model is left as it was)
};
/// q0 onto g = 0, then u0 onto G u = 0 (theory.md eqs. (M8), (M9): the least
/// change in A's metric), written into the model's joints when it converges.
/// Part of building a model, as finishMechanism is (call that first).
Assembly assembleStart(Model& m, double tol, int iterations);

/// The first closure a state leaves open by more than `tol` (m or rad, m/s or
/// rad/s): its index in Model::loops and "loop 'name' is open by 3.2e-4 m"
/// (or "... separates at 2e-3 m/s"); index -1 when every loop is closed.
struct LoopGap {
  int loop = -1;
  std::string what;
};
LoopGap openLoop(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u, double tol);

}  // namespace em
