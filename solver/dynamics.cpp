#include "solver/dynamics.hpp"
#include "solver/mechanism/loops.hpp"
#include "solver/applied_forces.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "solver/text.hpp"

namespace em {

namespace {
bool allFinite(const double* x, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(x[i])) return false;
  return true;
}

std::unique_ptr<MethodImpl> make(const Model& m, Method method, const MethodOptions& opt) {
  const MethodInfo& row = info(method);
  if (!row.make) throw std::invalid_argument(std::string(row.name) + " is not an in-house method");
  return row.make(m, row, opt);
}
}  // namespace

Dynamics::Dynamics(const Model& m, Method method, const MethodOptions& opt)
    : model_(m), method_(method), opt_(opt), f_(make(m, method, opt)),
      size_(m.nq + m.nu + extraStateSize(info(method).extra, m.nu) + (m.has_dampers ? 1 : 0)), ws_(m), scratch_(Eigen::VectorXd::Zero(size_)),
      loops_(m), solve_(m), project_(m), partition_(m), consistent_(partitions() ? size_ : 0), Gt_(m.nu, m.loop_rows), AinvGt_(m.nu, m.loop_rows),
      M_(m.loops.empty() ? 0 : m.nu, m.loops.empty() ? 0 : m.nu), llt_(m.nu) {}

Eigen::VectorXd Dynamics::initialState(const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(size_);
  y.head(model_.nq) = q;
  y.segment(model_.nq, model_.nu) = u;
  if (info(method_).extra != ExtraState::None) {
    formEquations(model_, y.data(), y.data() + model_.nq, ws_);
    f_->initialize(ws_, y.data() + offsetExtra());
  }
  return y;
}

namespace {

// Gimbals whose middle angle is within this of +-90 deg are named as the cause
// of a singular A (there A loses rank: docs/theory.md §1).
constexpr double kLockCos = 1e-3;

}  // namespace

std::string gimbalLockHint(const Model& m, const double* q) {
  std::string hint;
  for (const Body& b : m.bodies)
    if (jointRow(b.joint.type).middle_locks && std::abs(std::cos(q[b.iq + 1])) < kLockCos)
      hint += std::string(hint.empty() ? " (gimbal lock:" : ",") + " body '" + b.name + "' q1 = " + gnum(q[b.iq + 1]) + " rad";
  return hint.empty() ? hint : hint + ")";
}

Status Dynamics::rhs(double t, const double* y_in, double* dydt, EvalInfo* info) {
  const int nq = model_.nq;
  if (!allFinite(y_in, size_)) return Status::failure(t, Failure::NonFinite, "non-finite state (NaN or Inf)");
  const double* y = y_in;
  if (partitions()) {  // the ODE is the independent coordinates': the dependent ones follow (eq. (M12))
    consistent_ = Eigen::Map<const Eigen::VectorXd>(y_in, size_);
    if (Status s = partitionOntoLoops(t, consistent_.data(), false); !s) return s;
    y = consistent_.data();
  }
  formQdot(model_, y, y + nq, dydt);
  // A mechanism needs A for its multipliers and the kinematics for its point forces.
  const bool mechanism = model_.isMechanism(), loops = !model_.loops.empty();
  if (f_->needsEquations() || mechanism) formEquations(model_, y, y + nq, ws_, f_->needsAdot(), f_->needsA() || loops);
  else if (f_->needsKinematics()) formKinematics(model_, y, y + nq, ws_);
  EvalInfo local;
  Status s = f_->rates(t, y, y + nq, ws_, y + offsetExtra(), dydt + nq, dydt + offsetExtra(), info ? *info : local);
  if (s && loops) s = closeLoops(t, y, dydt + nq);
  if (model_.has_dampers)
    dydt[offsetDissipated()] = mechanism ? nonConservativePower(model_, ws_, y + nq) : dissipationRate(model_, y + nq);
  if (!s) s.cause += gimbalLockHint(model_, y);
  else if (!allFinite(dydt, size_)) return Status::failure(t, Failure::NonFinite, "non-finite derivative (NaN or Inf)");
  return s;
}

Status Dynamics::afterStep(double t, double* y, StepInfo& info) {
  normalizeQuaternions(model_, y);
  const int nq = model_.nq, N = model_.nu;
  if (!allFinite(y, size_)) return Status::failure(t, Failure::NonFinite, "non-finite state (NaN or Inf)");
  const double umax = Eigen::Map<const Eigen::VectorXd>(y + nq, N).cwiseAbs().maxCoeff();
  if (umax > opt_.blowup_speed)
    return Status::failure(t, Failure::BlowUp, "blow-up: max |u| = " + gnum(umax) + " exceeds " + gnum(opt_.blowup_speed));
  if (!model_.loops.empty()) {
    if (partitions()) {
      if (Status s = partitionOntoLoops(t, y, true); !s) return s;
    } else if (projects()) {
      if (Status s = projectOntoLoops(t, y); !s) return s;
    }
    formKinematics(model_, y, y + nq, ws_);
    formLoops(model_, ws_, y + nq, loops_);
    recordLoops();
    const double gap = std::max(loops_.position_m, loops_.position_rad);
    if (!(gap <= opt_.loops.loop_tol))
      return Status::failure(t, Failure::LoopsOpen, "the loops are open by " + gnum(gap, 3) + " (m or rad), beyond the loop tolerance " +
                                                        gnum(opt_.loops.loop_tol));
  }
  if (f_->needsAAfterStep()) {  // the correction needs A at the accepted state
    formKinematics(model_, y, y + nq, ws_);
    formSubtrees(model_, ws_);
    formA(model_, ws_);
  }
  return f_->afterStep(t, ws_, y + offsetExtra(), info);
}

const Eigen::MatrixXd& Dynamics::inverseATimesGt(const double* x) {
  Gt_.noalias() = loops_.G.transpose();
  if (f_->solveWithA(x, Gt_, AinvGt_)) return AinvGt_;
  llt_.compute(ws_.A);
  AinvGt_ = llt_.solve(Gt_);
  return AinvGt_;
}

const Eigen::MatrixXd& Dynamics::inverseSquareRoot(const double* x) {
  if (f_->inverseSquareRoot(x, M_)) return M_;
  llt_.compute(ws_.A);
  M_.setIdentity();
  llt_.matrixU().solveInPlace(M_);
  return M_;
}

// A non-finite A^-1 G^T or A^(-1/2): the method's own cause where it has one (a plugin's error).
Status Dynamics::solveFailed(double t, const char* otherwise) const {
  const std::string why = f_->solveFailure();
  return why.empty() ? Status::failure(t, Failure::NotPositiveDefinite, otherwise) : Status::failure(t, Failure::Plugin, why);
}

// u' = a + A^-1 G^T lambda (docs/theory.md eq. (M7)), a the tree's u' in udot;
// or Udwadia-Kalaba's u' = a + M (G M)^+ (b - G a) (eq. (M11)).
Status Dynamics::closeLoops(double t, const double* y, double* udot) {
  formLoops(model_, ws_, y + model_.nq, loops_);
  const LoopOptions& lo = opt_.loops;
  Eigen::Map<Eigen::VectorXd> a(udot, model_.nu);
  int rank = 0;
  if (lo.formulation == Formulation::UdwadiaKalaba) {
    const Eigen::MatrixXd& M = inverseSquareRoot(y + offsetExtra());
    if (!M.allFinite()) return solveFailed(t, "A^(-1/2) not finite (A not positive definite)");
    rank = solve_.solveUdwadiaKalaba(loops_, M, lo.alpha, lo.beta, a);
  } else {
    const Eigen::MatrixXd& AinvGt = inverseATimesGt(y + offsetExtra());
    if (!AinvGt.allFinite()) return solveFailed(t, "A^-1 G^T not finite (A not positive definite)");
    rank = solve_.solve(loops_, AinvGt, lo.alpha, lo.beta, a);
  }
  loop_stats_.rank_min = loop_stats_.rank_min < 0 ? rank : std::min(loop_stats_.rank_min, rank);
  loop_stats_.rank_max = std::max(loop_stats_.rank_max, rank);
  return {};
}

void Dynamics::recordLoops() { recordViolation(loops_, loop_stats_); }

// q onto g(q) = 0 by Gauss-Newton in A's metric, then u onto G u = 0
// (docs/theory.md eqs. (M8), (M9)).
Status Dynamics::projectOntoLoops(double t, double* y) {
  const LoopOptions& lo = opt_.loops;
  ++loop_stats_.projections;
  const LoopProjector::Result r = project_.positions(model_, ws_, y, y + model_.nq, lo.projection_tol, lo.projection_iterations);
  loop_stats_.projection_iterations += r.iterations;
  if (!r.finite) return Status::failure(t, Failure::NonFinite, "the projection met a non-finite loop gap");
  // Near a singular position Gauss-Newton converges slowly: the step goes on
  // unconverged, counted, and fails only where the gap passes loop_tol (afterStep).
  if (!r.converged) ++loop_stats_.projections_unconverged;
  project_.velocities(y + model_.nq);
  return {};
}

Status Dynamics::partitionOntoLoops(double t, double* y, bool accepted) {
  const LoopOptions& lo = opt_.loops;
  LoopStats& st = loop_stats_;
  if (!partition_.chosen()) {
    formKinematics(model_, y, y + model_.nq, ws_);
    formLoops(model_, ws_, y + model_.nq, loops_);
    partition_.choose(loops_);
  }
  ++st.newton_solves;
  const LoopProjector::Result r = partition_.dependent(model_, ws_, loops_, y, y + model_.nq, lo.projection_tol, lo.projection_iterations);
  st.newton_iterations += r.iterations;
  if (!r.finite) return Status::failure(t, Failure::NonFinite, "coordinate partitioning's Newton met a non-finite loop gap");
  if (!r.converged) ++st.newton_unconverged;  // goes on, counted; fails only beyond loop_tol (afterStep)
  if (!accepted) return {};
  if (partition_.degraded(loops_)) {  // chosen anew at the accepted state, which is on the loops
    partition_.choose(loops_);
    ++st.repartitions;
    if (st.repartition_times.size() < kRepartitionTimesKept) st.repartition_times.push_back(t);
  }
  if (partition_.bestPivotRatio() < kSingularPivotRatio)
    return Status::failure(t, Failure::Singular, "a singular position: the loops' Jacobian G is within " + gnum(partition_.bestPivotRatio(), 2) +
                                                     " (its smallest pivot over its largest) of losing rank, which coordinate partitioning "
                                                     "cannot pass (the projection formulation can)");
  return {};
}

void Dynamics::recordLoopsAt(const double* y) {
  formKinematics(model_, y, y + model_.nq, ws_);
  formLoops(model_, ws_, y + model_.nq, loops_);
  recordLoops();
}

void Dynamics::kinematicsAt(const double* y) {
  formKinematics(model_, y, y + model_.nq, ws_);
  formEnergies(model_, y, ws_);
}

double Dynamics::conditionAt(const double* y) {
  formKinematics(model_, y, y + model_.nq, ws_);
  formSubtrees(model_, ws_);
  formA(model_, ws_);
  return conditionNumber(ws_.A);
}

EigenDiagnostics Dynamics::diagnosticsAt(const double* y) {
  // A, A' and Omega at y, from a fresh evaluation.
  EvalInfo ev;
  const bool ok = rhs(0.0, y, scratch_.data(), &ev).ok;
  if (!f_->needsA()) formA(model_, ws_);  // the drift is measured against A itself
  return f_->diagnostics(ws_, y + offsetExtra(), ok ? ev.max_Omega : std::numeric_limits<double>::infinity());
}

}  // namespace em
