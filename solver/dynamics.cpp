#include "solver/dynamics.hpp"

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
      size_(m.nq + m.nu + extraStateSize(info(method).extra, m.nu) + (m.has_dampers ? 1 : 0)), ws_(m), scratch_(Eigen::VectorXd::Zero(size_)) {}

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

Status Dynamics::rhs(double t, const double* y, double* dydt, EvalInfo* info) {
  const int nq = model_.nq;
  if (!allFinite(y, size_)) return Status::failure(t, Failure::NonFinite, "non-finite state (NaN or Inf)");
  formQdot(model_, y, y + nq, dydt);
  if (f_->needsEquations()) formEquations(model_, y, y + nq, ws_, f_->needsAdot(), f_->needsA());
  else if (f_->needsKinematics()) formKinematics(model_, y, y + nq, ws_);
  EvalInfo local;
  Status s = f_->rates(t, y, y + nq, ws_, y + offsetExtra(), dydt + nq, dydt + offsetExtra(), info ? *info : local);
  if (model_.has_dampers) dydt[offsetDissipated()] = dissipationRate(model_, y + nq);
  if (!s) s.cause += gimbalLockHint(model_, y);
  else if (!allFinite(dydt, size_)) return Status::failure(t, Failure::NonFinite, "non-finite derivative (NaN or Inf)");
  return s;
}

void Dynamics::normalizeQuaternions(double* y) const {
  for (const Body& b : model_.bodies)
    if (const int at = jointQuat(b.joint.type); at >= 0) Eigen::Map<Vec4>(y + b.iq + at).normalize();
}

Status Dynamics::afterStep(double t, double* y, StepInfo& info) {
  normalizeQuaternions(y);
  const int nq = model_.nq, N = model_.nu;
  if (!allFinite(y, size_)) return Status::failure(t, Failure::NonFinite, "non-finite state (NaN or Inf)");
  const double umax = Eigen::Map<const Eigen::VectorXd>(y + nq, N).cwiseAbs().maxCoeff();
  if (umax > opt_.blowup_speed)
    return Status::failure(t, Failure::BlowUp, "blow-up: max |u| = " + gnum(umax) + " exceeds " + gnum(opt_.blowup_speed));
  if (f_->needsAAfterStep()) {  // the correction needs A at the accepted state
    formKinematics(model_, y, y + nq, ws_);
    formSubtrees(model_, ws_);
    formA(model_, ws_);
  }
  return f_->afterStep(t, ws_, y + offsetExtra(), info);
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
