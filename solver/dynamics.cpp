#include "solver/dynamics.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace em {

namespace {
const std::pair<Method, const char*> kMethods[] = {{Method::Classical, "classical"},
                                                   {Method::Eigen, "eigen"},
                                                   {Method::EigenJacobi, "eigen-jacobi"},
                                                   {Method::EigenJacobiOrth, "eigen-jacobi-orth"}};

bool allFinite(const double* x, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(x[i])) return false;
  return true;
}

std::string fmt(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}
}  // namespace

const char* methodName(Method m) {
  for (auto& [k, name] : kMethods)
    if (k == m) return name;
  return "?";
}

bool parseMethod(const std::string& s, Method& m) {
  for (auto& [k, name] : kMethods)
    if (s == name) { m = k; return true; }
  return false;
}

Dynamics::Dynamics(const Model& m, Method method, MethodOptions opt)
    : model_(m), method_(method), opt_(opt), ws_(m), llt_(m.nu), corr_(m.nu) {
  const int N = m.nu;
  size_ = m.nq + N + (eigenfactor() ? N * N + N : 0);
  G_.setZero(N, N);
  T1_.setZero(N, N);
  z_.setZero(N);
  stats.min_gap = std::numeric_limits<double>::infinity();
}

void Dynamics::fail(double t, const std::string& cause) {
  if (failure_.failed) return;  // keep the first cause
  failure_ = {true, t, cause};
}

Eigen::VectorXd Dynamics::initialState(const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(size_);
  y.head(model_.nq) = q;
  y.segment(model_.nq, model_.nu) = u;
  if (eigenfactor()) {
    // C(0) = V^T with A = V diag(lambda) V^T (docs/theory.md §7).
    const int N = model_.nu;
    formEquations(model_, y.data(), y.data() + model_.nq, ws_);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(ws_.A);
    Eigen::Map<RowMatrix>(y.data() + offsetC(), N, N) = es.eigenvectors().transpose();
    y.segment(offsetLambda(), N) = es.eigenvalues();
  }
  return y;
}

bool Dynamics::rhs(double t, const double* y, double* dydt) {
  ++rhs_evals;
  const int nq = model_.nq, N = model_.nu;
  const double* q = y;
  const double* u = y + nq;
  if (!allFinite(y, size_)) { fail(t, "non-finite state (NaN or Inf)"); return false; }
  formQdot(model_, q, u, dydt);
  Eigen::Map<Eigen::VectorXd> udot(dydt + nq, N);
  if (eigenfactor()) {
    if (!eigenRhs(t, y, dydt)) return false;
  } else {
    // Classical: u' from A u' = B by Cholesky (paper eq. (1)).
    formEquations(model_, q, u, ws_);
    llt_.compute(ws_.A);
    if (llt_.info() != Eigen::Success) { fail(t, "mass matrix A not positive definite (Cholesky failed)"); return false; }
    // A nearly singular A (a gimbal at +-90 deg) factors with a tiny positive
    // pivot and gives garbage: cond(A) >= max L_ii^2 / min L_ii^2 catches it.
    const auto pivots = llt_.matrixLLT().diagonal().cwiseAbs2();
    if (pivots.maxCoeff() > opt_.max_pivot_ratio * pivots.minCoeff()) {
      fail(t, "mass matrix A numerically singular: cond(A) >= " + fmt(pivots.maxCoeff() / pivots.minCoeff()) +
                  " > 1/eps (gimbal lock or extreme mass ratios)");
      return false;
    }
    udot = ws_.B;
    llt_.solveInPlace(udot);
  }
  if (!allFinite(dydt, size_)) { fail(t, "non-finite derivative (NaN or Inf)"); return false; }
  return true;
}

bool Dynamics::eigenRhs(double t, const double* y, double* dydt) {
  const int nq = model_.nq, N = model_.nu;
  formEquations(model_, y, y + nq, ws_, /*with_Adot=*/true);
  Eigen::Map<const RowMatrix> C(y + offsetC(), N, N);
  Eigen::Map<const Eigen::VectorXd> lambda(y + offsetLambda(), N);
  Eigen::Map<RowMatrix> Cdot(dydt + offsetC(), N, N);
  Eigen::Map<Eigen::VectorXd> lambda_dot(dydt + offsetLambda(), N);
  Eigen::Map<Eigen::VectorXd> udot(dydt + nq, N);
  // Hazards the harness must report, not hide (docs/theory.md §7).
  const double lmax = lambda.maxCoeff();
  for (int i = 0; i < N; ++i)
    if (!(lambda[i] > 0)) { fail(t, "eigenvalue lambda_" + std::to_string(i) + " = " + fmt(lambda[i]) + " <= 0"); return false; }
  const RateStatus st = eigenRates(C, lambda, ws_.Adot, opt_.gap_floor_rel * lmax, G_, T1_, lambda_dot, Cdot);
  if (!st.ok) {
    fail(t, "eigenvalue gap |lambda_" + std::to_string(st.i) + " - lambda_" + std::to_string(st.j) + "| = " +
                fmt(st.gap) + " below the floor " + fmt(opt_.gap_floor_rel * lmax));
    return false;
  }
  stats.max_abs_Omega = std::max(stats.max_abs_Omega, st.max_Omega);
  // u' = C^T Lambda^-1 C B (paper eq. (17)).
  z_.noalias() = C * ws_.B;
  z_.array() /= lambda.array();
  udot.noalias() = C.transpose() * z_;
  return true;
}

void Dynamics::normalizeQuaternions(double* y) const {
  for (const Body& b : model_.bodies)
    if (b.joint.type == JointType::Ball) Eigen::Map<Vec4>(y + b.iq).normalize();
}

bool Dynamics::postStep(double t, double* y) {
  normalizeQuaternions(y);
  const int nq = model_.nq, N = model_.nu;
  if (!allFinite(y, size_)) { fail(t, "non-finite state (NaN or Inf)"); return false; }
  const double umax = Eigen::Map<const Eigen::VectorXd>(y + nq, N).cwiseAbs().maxCoeff();
  if (umax > opt_.blowup_speed) { fail(t, "blow-up: max |u| = " + fmt(umax) + " exceeds " + fmt(opt_.blowup_speed)); return false; }
  if (!eigenfactor()) return true;
  Eigen::Map<RowMatrix> C(y + offsetC(), N, N);
  Eigen::Map<Eigen::VectorXd> lambda(y + offsetLambda(), N);
  if (method_ == Method::EigenJacobi || method_ == Method::EigenJacobiOrth) {
    if (method_ == Method::EigenJacobiOrth) symmetricOrthonormalize(C, corr_);
    formKinematics(model_, y, y + nq, ws_);
    formK(model_, ws_);
    formA(model_, ws_);
    const JacobiStats st = jacobiCorrect(ws_.A, C, lambda, corr_, opt_.jacobi_tol, opt_.jacobi_max_sweeps);
    stats.jacobi_sweeps += st.sweeps;
    stats.jacobi_rotations += st.rotations;
    stats.jacobi_single_sweep_steps += st.sweeps <= 1;
    stats.jacobi_max_sweeps = std::max(stats.jacobi_max_sweeps, st.sweeps);
    if (!st.converged) {
      const double orth = (C * C.transpose() - Eigen::MatrixXd::Identity(N, N)).norm();
      fail(t, "Jacobi correction did not converge in " + std::to_string(opt_.jacobi_max_sweeps) +
                  " sweeps (off(C A C^T)/||A|| = " + fmt(offDiagonalNorm(corr_.D) / ws_.A.norm()) +
                  ", ||C C^T - I|| = " + fmt(orth) + ")");
      return false;
    }
  }
  const double gap = minEigenGap(lambda);
  if (gap < stats.min_gap) { stats.min_gap = gap; stats.min_gap_time = t; }
  return true;
}

double Dynamics::energyAt(const double* y) {
  formKinematics(model_, y, y + model_.nq, ws_);
  return ws_.energy();
}

EigenDiagnostics Dynamics::diagnosticsAt(const double* y) {
  const int N = model_.nu;
  // Refresh A, A' and Omega at y without touching the run's counters or failure.
  std::vector<double> scratch(size_);
  const long evals = rhs_evals;
  const Failure saved = failure_;
  const EigenStats seen = stats;
  const bool ok = rhs(0.0, y, scratch.data());
  rhs_evals = evals;
  failure_ = saved;
  stats = seen;
  const double wmax = ok ? G_.cwiseAbs().maxCoeff() : std::numeric_limits<double>::infinity();
  return eigenDiagnostics(ws_.A, Eigen::Map<const RowMatrix>(y + offsetC(), N, N),
                          Eigen::Map<const Eigen::VectorXd>(y + offsetLambda(), N), wmax);
}

}  // namespace em
