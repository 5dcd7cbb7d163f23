// The index-3 augmented Lagrangian with mass-orthogonal projections under the
// trapezoidal rule (docs/theory.md eq. (M13)).
#include "solver/augmented_lagrangian.hpp"

#include "solver/applied_forces.hpp"
#include "solver/mechanism/constrained.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "solver/text.hpp"

namespace em {

int firstQuaternionBody(const Model& m) {
  for (int i = 0; i < m.n(); ++i)
    if (jointQuat(m.bodies[i].joint.type) >= 0) return i;
  return -1;
}

namespace {

// How far above its tolerance a Newton step that stopped shrinking counts as round-off (step()).
constexpr double kNewtonRoundoff = 1e2;

// T and P through A's tree factors where its pattern pays and no point spring fills the tangent.
bool sparsePath(const Model& m) { return TreeCholesky::pays(m) && m.point_springs.empty(); }

// The dense path's matrices' size: none on the sparse path (they would cost nu^2 memory there).
int denseDim(const Model& m) { return sparsePath(m) ? 0 : m.nu; }

}  // namespace

AugmentedLagrangianRun::AugmentedLagrangianRun(const Model& m, const LoopOptions& o, double dt, const double* y)
    : m_(m), o_(o), dt_(dt), ws_(m), loops_(m), qn_(Eigen::Map<const Eigen::VectorXd>(y, m.nq)),
      un_(Eigen::Map<const Eigen::VectorXd>(y + m.nq, m.nu)), udn_(m.nu), lambda_(Eigen::VectorXd::Zero(m.loop_rows)), q_(m.nq), delta_(m.nu),
      u_(m.nu), ud_(m.nu), f_(m.nu), dq_(m.nu), T_(denseDim(m), denseDim(m)), P_(denseDim(m), denseDim(m)), C_(denseDim(m), denseDim(m)),
      K_(denseDim(m), denseDim(m)), J_(3, m.nu), x_(m.nu), rows_(m.loop_rows), extra_(Eigen::VectorXd::Zero(m.nu)),
      sparse_(sparsePath(m)), tree_(m), cs_(m), lu_(denseDim(m)), llt_(denseDim(m)), rank_qr_(sparse_ ? 0 : m.loop_rows, denseDim(m)) {
  if (firstQuaternionBody(m) >= 0) throw std::invalid_argument("integrator trapezoidal integrates q' = u: not on quaternion joints");
  rank_qr_.setThreshold(kLoopRankTol);
  // u'(0) and the multipliers of eq. (M7): A u' = B + G^T lambda, so the residual's lambda* is -lambda.
  formEquations(m, qn_.data(), un_.data(), ws_);
  const ConstrainedEquations start = constrainedAt(m, ws_, un_.data());
  udn_ = start.udot;
  if (m.loop_rows) {
    lambda_ = -start.lambda;
    // alpha weighs the loops penalty_ratio times the inertia in T (largest diagonals).
    const double GtG = start.loops.G.colwise().squaredNorm().maxCoeff();  // max diag G^T G
    if (GtG > 0) alpha_ = o.penalty_ratio * 4.0 * ws_.A.diagonal().maxCoeff() / (dt * dt * GtG);
  }
  if (m.has_dampers) power_n_ = nonConservativePower(m, ws_, un_.data());
  if (sparse_ && m.has_springs) {  // the joints' C and K: constant, diagonal
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(m.nu, m.nu), K = C;
    addForceTangent(m, ws_, C, K, J_);
    extra_ = (dt / 2) * C.diagonal() + (dt * dt / 4) * K.diagonal();
  }
}

void AugmentedLagrangianRun::form(const double* q, const double* u) {
  formEquations(m_, q, u, ws_);
  if (m_.loop_rows) formLoops(m_, ws_, u, loops_);
  ++evaluations_;
}

// The increment delta_ = q - q_n is Newton's unknown, kept apart from q: formed
// as a difference of q's, the (4/dt^2)(q - q_n) of u'* would carry q's round-off
// (1e-14 rad once a crank has turned 100 rad) times 4/dt^2, and below dt 2e-4 on
// IFToMM A02 the error grew as dt fell (docs/results.md, "A02 through its
// singular positions").
void AugmentedLagrangianRun::trial() {
  q_ = qn_ + delta_;
  u_ = (2.0 / dt_) * delta_ - un_;
  ud_ = (4.0 / (dt_ * dt_)) * delta_ - (4.0 / dt_) * un_ - udn_;
}

// T = A + (dt/2) C + (dt^2/4)(K + alpha G^T G) at the formed q_, u_: C and K the
// applied forces' damping and stiffness (eq. (M13a)), which the tangent needs on
// stiff scenes (IFToMM A05: without them Newton diverged at dt 1e-2 and 1e-3).
// A's and the velocity terms' derivatives are left out, as in ALI3-P: they slow
// Newton, they do not move its root.
void AugmentedLagrangianRun::tangent() {
  T_ = ws_.A;
  if (m_.hasAppliedForces()) {
    C_.setZero();
    K_.setZero();
    addForceTangent(m_, ws_, C_, K_, J_);
    T_ += (dt_ / 2) * C_ + (dt_ * dt_ / 4) * K_;
  }
  if (m_.loop_rows) addLoopGramian(m_, loops_.G, dt_ * dt_ / 4 * alpha_, T_);
}

// dq_ = -T^-1 f_. Dense: T by LU. Sparse (A's tree pattern pays, the applied
// forces' C and K diagonal): x = Abar^-1 f by Abar's tree factors, Abar = A +
// (h/2) C + (h^2/4) K, and T^-1 f = x - Abar^-1 G^T (shift I + G Abar^-1 G^T)^-1 G x,
// shift = 1 / ((h^2/4) alpha) (Woodbury, docs/theory.md eq. (S4)): linear cost.
bool AugmentedLagrangianRun::newtonStep() {
  if (!sparse_) {
    tangent();
    lu_.compute(T_);
    dq_ = -lu_.solve(f_);
    return true;
  }
  if (!tree_.factor(ws_.A, extra_)) return false;
  dq_ = f_;
  tree_.solveInPlace(dq_.data());
  if (m_.loop_rows) {
    cs_.timesG(loops_, dq_, rows_);
    cs_.factorPenalty(loops_, tree_, 1.0 / (dt_ * dt_ / 4 * alpha_));
    cs_.penaltySolve(tree_, rows_, x_);
    dq_ -= x_;
  }
  dq_ = -dq_;
  return true;
}

// The mass-orthogonal projections at q_{n+1} (formed), P = A + (h^2/4) alpha G^T G:
// u -= P^-1 (h^2/4) alpha G^T G u, u' -= P^-1 (h^2/4) alpha G^T (G u' + c); the
// rank of G. Sparse: P^-1 (h^2/4) alpha G^T r = A^-1 G^T (shift I + G A^-1 G^T)^-1 r (eq. (S4)).
int AugmentedLagrangianRun::project() {
  const double h2 = dt_ * dt_ / 4.0;
  int rank = 0;
  if (sparse_) {
    tree_.factor(ws_.A);  // positive definite: the formation's A
    rank = cs_.rankOf(loops_, tree_);
    cs_.factorPenalty(loops_, tree_, 1.0 / (h2 * alpha_));
    cs_.penaltySolve(tree_, loops_.Gu, x_);
    u_ -= x_;
  } else {
    P_ = ws_.A;
    addLoopGramian(m_, loops_.G, h2 * alpha_, P_);
    llt_.compute(P_);
    f_.noalias() = (h2 * alpha_) * loops_.G.transpose() * loops_.Gu;
    u_ -= llt_.solve(f_);
  }
  formKinematics(m_, q_.data(), u_.data(), ws_);  // c at the projected u
  formLoops(m_, ws_, u_.data(), loops_);
  if (sparse_) {
    cs_.timesG(loops_, ud_, rows_);
    rows_ += loops_.c;
    cs_.penaltySolve(tree_, rows_, x_);
    ud_ -= x_;
  } else {
    f_.noalias() = (h2 * alpha_) * loops_.G.transpose() * (loops_.G * ud_ + loops_.c);
    ud_ -= llt_.solve(f_);
    rank_qr_.compute(loops_.G);
    rank = static_cast<int>(rank_qr_.rank());
  }
  return rank;
}

Status AugmentedLagrangianRun::step(double t, double* y) {
  const double h2 = dt_ * dt_ / 4.0;
  delta_ = dt_ * un_ + (dt_ * dt_ / 2.0) * udn_;  // the predictor
  ++stats_.newton_solves;
  bool converged = false;
  double last = INFINITY;  // the previous Newton step's max |dq|
  int it = 0;
  for (;; ++it) {
    trial();
    form(q_.data(), u_.data());
    if (it > 0 && m_.loop_rows) lambda_ += alpha_ * loops_.g;  // lambda*_{i+1} = lambda*_i + alpha g(q_{i+1})
    // f = (dt^2/4)(A u'* - B + G^T (lambda* + alpha g)), T = A + (dt/2) C + (dt^2/4)(K + alpha G^T G).
    if (sparse_) tree_.multiply(ws_.A, ud_.data(), f_.data());  // A u'* over A's tree pattern: linear cost
    else f_.noalias() = ws_.A * ud_;
    f_ -= ws_.B;
    if (m_.loop_rows) {  // G^T (lambda* + alpha g) over the loops' speeds: linear cost
      rows_ = lambda_ + alpha_ * loops_.g;
      cs_.addTimesGt(loops_, rows_, f_);
    }
    f_ *= h2;
    if (!newtonStep()) return Status::failure(t, Failure::NonFinite, "the augmented Lagrangian's tangent is not positive definite");
    if (!dq_.allFinite()) return Status::failure(t, Failure::NonFinite, "the augmented Lagrangian's Newton step is not finite");
    delta_ += dq_;
    q_ = qn_ + delta_;
    ++stats_.newton_iterations;
    const double size = dq_.cwiseAbs().maxCoeff();
    if (size <= o_.al_tol) {
      converged = true;
      break;
    }
    // At round-off: a step that no longer shrinks at all (this modified Newton, its tangent without A's and the
    // velocity terms' derivatives, shrinks linearly, and steadily, above round-off) and is already within
    // kNewtonRoundoff of the tolerance moves q by round-off alone. On a row of 160 four-bars the absolute
    // 1e-12 lies below it: 130 of 1000 steps ran to the 30-iteration bound, and the route's cost grew as
    // N^1.6 (docs/performance.md). A looser rule (a step not shrinking by four, within 1e3 of the
    // tolerance) stopped A02's finest steps early: the six-turn test's error rose tenfold.
    if (size >= 0.9 * last && size <= kNewtonRoundoff * o_.al_tol) {
      converged = true;
      ++stats_.newton_at_roundoff;
      break;
    }
    last = size;
    if (it + 1 == o_.al_iterations) break;
  }
  if (!converged) ++stats_.newton_unconverged;  // goes on, counted; the run fails only beyond loop_tol
  // The state at q_{n+1}: lambda* takes its last update, then the mass-orthogonal projections
  // u = u* - T^-1 (dt^2/4) alpha G^T G u*, u' = u'* - T^-1 (dt^2/4) alpha G^T (G u'* + c).
  trial();
  form(q_.data(), u_.data());
  if (m_.loop_rows) {
    lambda_ += alpha_ * loops_.g;
    const int rank = project();
    stats_.rank_min = stats_.rank_min < 0 ? rank : std::min(stats_.rank_min, rank);
    stats_.rank_max = std::max(stats_.rank_max, rank);
  }
  double* W = m_.has_dampers ? y + m_.nq + m_.nu : nullptr;
  if (W) {  // W_diss by the same trapezoidal rule
    const double power = nonConservativePower(m_, ws_, u_.data());
    *W += dt_ / 2 * (power_n_ + power);
    power_n_ = power;
  }
  qn_ = q_;
  un_ = u_;
  udn_ = ud_;
  Eigen::Map<Eigen::VectorXd>(y, m_.nq) = q_;
  Eigen::Map<Eigen::VectorXd>(y + m_.nq, m_.nu) = u_;
  return {};
}

}  // namespace em
