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
      size_(m.nq + m.nu + extraStateSize(info(method).extra, m.nu) + (m.has_dampers ? 1 : 0)), ws_(m), control_(m), scratch_(Eigen::VectorXd::Zero(size_)),
      form_(m.loops.empty() ? nullptr : formulationRow(opt.loops.formulation).make(m, opt.loops)), factors_(*this),
      Gt_(m.nu, m.loop_rows), AinvGt_(m.nu, m.loop_rows), M_(m.loops.empty() ? 0 : m.nu, m.loops.empty() ? 0 : m.nu), llt_(m.nu),
      tree_(!m.loops.empty() && !f_->treeFactor() && !f_->hasOwnInverse() && TreeCholesky::pays(m) ? std::make_unique<TreeCholesky>(m)
                                                                                                   : nullptr) {}

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
  const double* y = y_in;  // or (coordinate partitioning) y with its dependent coordinates solved
  if (form_)
    if (Status s = form_->evaluationState(t, ws_, y_in, size_, y); !s) return s;
  formQdot(model_, y, y + nq, dydt);
  if (control_.active()) control_.torques(t, y, y + nq, ws_.control);  // B gains them (theory.md eq. (C1))
  // A mechanism needs A for its multipliers and the kinematics for its point forces.
  const bool mechanism = model_.isMechanism(), loops = !model_.loops.empty();
  if (f_->needsEquations() || mechanism) formEquations(model_, y, y + nq, ws_, f_->needsAdot(), f_->needsA() || loops);
  else if (f_->needsKinematics()) formKinematics(model_, y, y + nq, ws_);
  EvalInfo local;
  Status s = f_->rates(t, y, y + nq, ws_, y + offsetExtra(), dydt + nq, dydt + offsetExtra(), info ? *info : local);
  if (s && loops) s = form_->accelerations(t, ws_, y, y + offsetExtra(), factors_, dydt + nq);
  if (model_.has_dampers)
    dydt[offsetDissipated()] = mechanism || model_.has_control ? nonConservativePower(model_, ws_, y + nq) : dissipationRate(model_, y + nq);
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
  if (form_) {
    if (Status s = form_->afterStep(t, ws_, y); !s) return s;
    formKinematics(model_, y, y + nq, ws_);
    formLoops(model_, ws_, y + nq, form_->loops());
    recordLoops();
    if (Status s = loopsOpen(t); !s) return s;
  }
  if (f_->needsAAfterStep()) {  // the correction needs A at the accepted state
    formKinematics(model_, y, y + nq, ws_);
    formSubtrees(model_, ws_);
    formA(model_, ws_);
  }
  return f_->afterStep(t, ws_, y + offsetExtra(), info);
}

const Eigen::MatrixXd& Dynamics::Factors::inverseATimesGt(const double* extra, const LoopState& ls) {
  d_.Gt_.noalias() = ls.G.transpose();
  if (d_.f_->solveWithA(extra, d_.Gt_, d_.AinvGt_)) return d_.AinvGt_;
  d_.llt_.compute(d_.ws_.A);
  d_.AinvGt_ = d_.llt_.solve(d_.Gt_);
  return d_.AinvGt_;
}

const TreeCholesky* Dynamics::Factors::treeFactor(const double*) {
  if (const TreeCholesky* own = d_.f_->treeFactor()) return own;
  if (!d_.tree_ || !d_.tree_->factor(d_.ws_.A)) return nullptr;  // not positive definite: the dense path says so
  return d_.tree_.get();
}

const Eigen::MatrixXd& Dynamics::Factors::inverseSquareRoot(const double* extra) {
  if (d_.f_->inverseSquareRoot(extra, d_.M_)) return d_.M_;
  d_.llt_.compute(d_.ws_.A);
  d_.M_.setIdentity();
  d_.llt_.matrixU().solveInPlace(d_.M_);
  return d_.M_;
}

// A non-finite A^-1 G^T or A^(-1/2): the method's own cause where it has one (a plugin's error).
Status Dynamics::Factors::solveFailed(double t, const char* otherwise) const {
  const std::string why = d_.f_->solveFailure();
  return why.empty() ? Status::failure(t, Failure::NotPositiveDefinite, otherwise) : Status::failure(t, Failure::Plugin, why);
}

Status Dynamics::loopsOpen(double t) const {
  if (!form_) return {};
  const LoopState& loops = form_->loops();
  const double gap = std::max(loops.position_m, loops.position_rad);
  if (gap <= opt_.loops.loop_tol) return {};
  return Status::failure(t, Failure::LoopsOpen, "the loops are open by " + gnum(gap, 3) + " (m or rad), beyond the loop tolerance " +
                                                    gnum(opt_.loops.loop_tol));
}

void Dynamics::recordLoops() { recordViolation(form_->loops(), form_->stats()); }

void Dynamics::recordLoopsAt(const double* y) {
  if (!form_) return;
  formKinematics(model_, y, y + model_.nq, ws_);
  formLoops(model_, ws_, y + model_.nq, form_->loops());
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
