#pragma once
/// The ODE right-hand side of each method (docs/theory.md §7–8): classical
/// (Cholesky of A every evaluation), eigen (Junkins–Schaub, uncorrected),
/// eigen-jacobi (Jacobi re-diagonalization after every accepted step) and
/// eigen-jacobi-orth (plus symmetric re-orthonormalization of C).
#include <string>

#include "solver/eigenfactor.hpp"
#include "solver/formation.hpp"
#include "solver/trajectory.hpp"

namespace em {

enum class Method { Classical, Eigen, EigenJacobi, EigenJacobiOrth };

const char* methodName(Method m);
/// Parse a method name; false if unknown.
bool parseMethod(const std::string& s, Method& m);

/// Numerical-failure thresholds and the correction's tolerance.
struct MethodOptions {
  double jacobi_tol = 1e-13;  ///< stop when off(C A C^T) <= tol ||A||_F
  int jacobi_max_sweeps = 50;
  double gap_floor_rel = 1e-12;  ///< fail when min |lambda_i - lambda_j| < floor * max lambda
  double blowup_speed = 1e6;     ///< fail when max |u| exceeds this (rad/s): the run has blown up
  /// Fail when max/min squared Cholesky pivot, a lower bound on cond(A), exceeds
  /// 1/eps: u' then has no reliable digit (gimbal lock, extreme mass ratios).
  double max_pivot_ratio = 4.5e15;
};

/// Why and when a run ended early.
struct Failure {
  bool failed = false;
  double t = 0;
  std::string cause;
};

/// One method's dynamics on one model: state layout, right-hand side, the
/// per-step correction and counters. Owns its preallocated workspace.
/// State y = [q (nq), u (nu), C (N*N, row-major, rows = eigenvectors), lambda (N)];
/// the last two only for the eigenfactor methods (N = nu).
class Dynamics {
 public:
  Dynamics(const Model& m, Method method, MethodOptions opt = {});

  const Model& model() const { return model_; }
  Method method() const { return method_; }
  bool eigenfactor() const { return method_ != Method::Classical; }
  int size() const { return size_; }
  int offsetC() const { return model_.nq + model_.nu; }
  int offsetLambda() const { return offsetC() + model_.nu * model_.nu; }

  /// y0 from (q, u) (internal order); C(0), lambda(0) from an eigensolver of A(q).
  Eigen::VectorXd initialState(const Eigen::VectorXd& q, const Eigen::VectorXd& u);
  /// dy/dt at (t, y). False on a numerical failure (recorded in failure()).
  bool rhs(double t, const double* y, double* dydt);
  /// After every accepted step: normalize quaternions, apply the method's
  /// correction, check for blow-up. False on failure.
  bool postStep(double t, double* y);
  /// Energy and the workspace kinematics at y (for output).
  double energyAt(const double* y);
  /// Eigenfactor drift diagnostics at y (eigenfactor methods only).
  EigenDiagnostics diagnosticsAt(const double* y);

  const Failure& failure() const { return failure_; }
  void fail(double t, const std::string& cause);
  Workspace& workspace() { return ws_; }

  long rhs_evals = 0;
  EigenStats stats;

 private:
  bool eigenRhs(double t, const double* y, double* dydt);
  void normalizeQuaternions(double* y) const;

  const Model& model_;
  Method method_;
  MethodOptions opt_;
  int size_;
  Workspace ws_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::MatrixXd G_, T1_;  // (N x N) scratch: C A' C^T and A' C^T
  Eigen::VectorXd z_;        // (N) scratch
  CorrectionScratch corr_;
  Failure failure_;
};

}  // namespace em
