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
  /// The largest |g| over the ball rows (m) and over the axis rows (rad), and
  /// the same of G u (m/s, rad/s): what a report calls the violation.
  double position_m = 0, position_rad = 0, velocity_m = 0, velocity_rad = 0;
};
/// g, G, G u and c at the formed kinematics.  // u: (nu)
void formLoops(const Model& m, const Workspace& ws, const double* u, LoopState& ls);

/// Q += the joint springs', the drives' and the point spring-dampers'
/// generalized forces (theory.md eq. (M5)).  // q: (nq), u, Q: (nu)
void addAppliedForces(const Model& m, const Workspace& ws, const double* q, const double* u, Eigen::VectorXd& Q);
/// Potential of the point springs, sum of k (l - length)^2 / 2.
double pointSpringPotential(const Model& m, const Workspace& ws);
/// dW_diss/dt: the power the joint and point dampers dissipate minus the
/// power the drives put in (theory.md eq. (M6)); E + W_diss is conserved.
double nonConservativePower(const Model& m, const Workspace& ws, const double* u);

/// The rank threshold of G A^-1 G^T, relative to its largest pivot: rows
/// beyond the rank are redundant (a planar mechanism closed by balls, Bricard).
inline constexpr double kLoopRankTol = 1e-10;

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
  /// out = A^-1 G^T (G A^-1 G^T)^+ r: the least change in A's metric that
  /// takes G's rows by r (a projection's step).  // r: (m), out: (nu)
  void correction(const LoopState& ls, const Eigen::MatrixXd& AinvGt, const Eigen::VectorXd& r, Eigen::VectorXd& out);
  const Eigen::VectorXd& lambda() const { return lambda_; }
  int rank() const { return rank_; }

 private:
  Eigen::MatrixXd S_;
  Eigen::VectorXd r_, lambda_;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_;
  int rank_ = 0;
};

/// Set each weld's relative orientation from the model's initial state
/// (Loop::rel); a model without welds is left as it is.
void finishMechanism(Model& m);

/// The first closure a state leaves open by more than `tol` (m or rad, m/s or
/// rad/s): its index in Model::loops and "loop 'name' is open by 3.2e-4 m"
/// (or "... separates at 2e-3 m/s"); index -1 when every loop is closed.
struct LoopGap {
  int loop = -1;
  std::string what;
};
LoopGap openLoop(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u, double tol);

}  // namespace em
