#pragma once
/// The index-3 augmented Lagrangian with mass-orthogonal projections under the
/// trapezoidal rule (Bayo and Ledesma 1996; the ALI3-P of Cuadrado, Dopico,
/// González and Naya, behind IFToMM's reference solutions; docs/theory.md
/// eq. (M13)): the formulation `augmented-lagrangian`, run by the integrator
/// `trapezoidal`. Each step solves, by Newton with the tangent
/// T = A + (dt/2) C + (dt^2/4) (K + alpha G^T G), C and K the applied forces'
/// damping and stiffness in closed form (addForceTangent, eq. (M13a)),
///   (dt^2/4) (A u'* - B + G^T (lambda* + alpha g)) = 0,
///   u* = (2/dt)(q - q_n) - u_n,  u'* = (4/dt^2)(q - q_n) - (4/dt) u_n - u'_n,
/// with lambda* += alpha g at every iterate, then projects u and u'
/// mass-orthogonally onto G u = 0 and G u' + c = 0. On a tree (no loops) it is
/// the implicit trapezoidal rule on A u' = B. It integrates q' = u: no
/// quaternion joints (ball, free). A, B and g are the formation's and
/// solver/mechanism's; the solves are its own (Cholesky of T).
#include "solver/mechanism/constrained.hpp"
#include "solver/mechanism/loops.hpp"
#include "solver/tree_cholesky.hpp"
#include "solver/method.hpp"

namespace em {

class AugmentedLagrangianRun {
 public:
  /// At the state y (q, u, [W_diss], laid out as Dynamics does for a method
  /// without extra state); u'(0) and lambda*(0) from the constrained equations
  /// (eq. (M7)). Throws std::invalid_argument where the model has a quaternion joint.
  AugmentedLagrangianRun(const Model& m, const LoopOptions& o, double dt, const double* y);
  /// One step of dt from the state of the last step (or the start) into y.
  Status step(double t, double* y);
  const LoopStats& stats() const { return stats_; }  ///< Newton steps and iterations, the rank of G
  long evaluations() const { return evaluations_; }  ///< formations of A and B
  double penalty() const { return alpha_; }          ///< alpha (1/s^2 per unit of A over G^T G)

 private:
  void form(const double* q, const double* u);  // ws_: A, B and the loops at (q, u)
  void trial();                                 // q, u*, u'* from the increment delta_ = q - q_n
  void tangent();                               // T_ at the formed q_, u_ (dense path)
  bool newtonStep();                            // dq_ = -T^-1 f_
  int project();                                // u_, ud_ projected at the formed q_; the rank of G
  const Model& m_;
  LoopOptions o_;
  double dt_, alpha_ = 0;
  Workspace ws_;
  LoopState loops_;
  Eigen::VectorXd qn_, un_, udn_, lambda_, q_, delta_, u_, ud_, f_, dq_;
  Eigen::MatrixXd T_, P_, C_, K_, J_;  // Newton's tangent, the projections' A + (dt^2/4) alpha G^T G, damping, stiffness, a spring's J_d
  Eigen::VectorXd x_, rows_, extra_;    // (nu) scratch, (m) G x, the joints' (h/2) c + (h^2/4) k
  bool sparse_;                         // T and P through A's tree factors (TreeCholesky::pays, no point spring)
  TreeCholesky tree_;
  ConstrainedSolve cs_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> rank_qr_;
  double power_n_ = 0;  // the non-conservative power at the last step (W_diss by the trapezoidal rule)
  LoopStats stats_;
  long evaluations_ = 0;
};

/// The first body whose joint the trapezoidal rule cannot integrate (a
/// quaternion: q' is not u), or -1.
int firstQuaternionBody(const Model& m);

}  // namespace em
