#pragma once
/// A method's own code (docs/theory.md §8), MethodImpl: how it starts its
/// extra state (laid out as its row's ExtraState says), how it gets u' from
/// the formed equations, and what it does after an accepted step. The
/// registry's row builds it (MethodInfo::make); Dynamics drives it. Also the
/// pieces the eigenfactor methods share (eigen, eigen-block).
#include <limits>
#include <memory>
#include <string>

#include "solver/eigenfactor_ops.hpp"
#include "solver/formation.hpp"
#include "solver/method_options.hpp"
#include "solver/registry.hpp"
#include "solver/tree_cholesky.hpp"

namespace em {

/// Outcome of an evaluation or a correction: ok, or a numerical failure at t with its cause.
struct Status {
  bool ok = true;
  double t = 0;
  Failure kind = Failure::None;
  std::string cause;
  static Status failure(double t, Failure kind, std::string cause) { return {false, t, kind, std::move(cause)}; }
  explicit operator bool() const { return ok; }
};

/// What one evaluation measured beside the derivative.
struct EvalInfo {
  double max_Omega = 0;  ///< max |Omega_ij| (eigenfactor methods)
};

/// What the method did after one accepted step.
struct StepInfo {
  bool corrected = false;  ///< a correction ran (its Jacobi statistics below)
  JacobiStats jacobi;
  double min_gap = std::numeric_limits<double>::infinity();  ///< smallest eigenvalue gap after it
  int merges = 0, splits = 0;  ///< eigen-block: clusters joined and broken up by this step's re-clustering
};

class MethodImpl {
 public:
  virtual ~MethodImpl() = default;
  /// Whether the evaluation needs A u' = B formed; false: Dynamics forms only
  /// the kinematics (formKinematics) and rates() works from them and (q, u)
  /// (the articulated-body method).
  virtual bool needsEquations() const { return true; }
  /// Whether the evaluation needs the kinematics formed when it needs no
  /// equations (the articulated-body method); false: rates() works from
  /// (q, u) alone (a method whose u' comes from another library, a plugin).
  virtual bool needsKinematics() const { return true; }
  /// Whether the evaluation needs A' formed (the eigenfactor rates do).
  virtual bool needsAdot() const { return false; }
  /// Whether the evaluation reads A (classical factors it; the eigenfactor
  /// methods only for residual corrections).
  virtual bool needsA() const { return true; }
  /// The extra state at t = 0 from the formed A.  // x: (extraStateSize)
  virtual void initialize(const Workspace&, double* /*x*/) {}
  /// u' and the extra state's rates at (q, u) from the formed A, B (and A').  // q: (nq), u, udot: (nu), x, xdot: (extraStateSize)
  virtual Status rates(double t, const double* q, const double* u, const Workspace& ws, const double* x, double* udot,
                       double* xdot, EvalInfo& info) = 0;
  /// out = A^-1 X with the method's own factors of the A its last rates()
  /// had (classical: its Cholesky; the eigenfactor methods: C^T Lambda^-1 C
  /// from x), for a mechanism's multipliers; false: Dynamics factors A itself.  // X, out: (nu x m)
  virtual bool solveWithA(const double* /*x*/, const Eigen::MatrixXd& /*X*/, Eigen::MatrixXd& /*out*/) { return false; }
  /// Whether solveWithA answers (its A^-1 is the method's own: the eigenfactors',
  /// a plugin's); false: Dynamics factors the formed A itself.
  virtual bool hasOwnInverse() const { return false; }
  /// A's tree-sparse factors from its last rates() (classical where the tree's
  /// pattern pays: TreeCholesky::pays), for a mechanism's multipliers at linear
  /// cost (docs/theory.md §16); nullptr: none.
  virtual const TreeCholesky* treeFactor() const { return nullptr; }
  /// M with M M^T = A^-1 from the same factors (classical: L^-T; the
  /// eigenfactor methods: C^T Lambda^(-1/2)), for Udwadia-Kalaba's constrained
  /// acceleration; false: Dynamics factors A itself.  // M: (nu x nu)
  virtual bool inverseSquareRoot(const double* /*x*/, Eigen::MatrixXd& /*M*/) { return false; }
  /// Why the last solveWithA or inverseSquareRoot gave a non-finite result,
  /// where the method knows more than "not finite" (a plugin's own message); "" otherwise.
  virtual std::string solveFailure() const { return ""; }
  /// Whether afterStep changes the state (the integrator must then restart).
  virtual bool correctsAfterStep() const { return false; }
  /// Whether afterStep needs A formed at the accepted state.
  virtual bool needsAAfterStep() const { return correctsAfterStep(); }
  /// After an accepted step: correct the extra state (ws holds A at that state
  /// when needsAAfterStep()) and report what was done.
  virtual Status afterStep(double t, const Workspace& ws, double* x, StepInfo& info);
  /// Drift of the extra state against a fresh factorization of ws.A.
  virtual bool hasDiagnostics() const { return false; }
  virtual EigenDiagnostics diagnostics(const Workspace& ws, const double* x, double max_Omega) const;
};

// What the eigenfactor methods share (solver/method_eigen.cpp, solver/method_eigen_block.cpp).

/// C(0) = V^T and lambda from A = V diag(lambda) V^T (docs/theory.md §7).  // C: (N x N), lambda: (N)
void startFromEigensolver(const Eigen::MatrixXd& A, Eigen::Ref<RowMatrix> C, Eigen::Ref<Eigen::VectorXd> lambda);

/// u' = H B, then `refine` residual corrections u' += H (B - A u') (docs/theory.md
/// §8, eq. (R)), H the eigenfactors' inverse applied as applyH(b, out);
/// the refinement-diverged failure at t when a correction grows the residual,
/// refinement-not-converged when the last one leaves the relative residual
/// above `tol` (the row option refine_tol; eq. (R')).
template <class ApplyH>
Status solveByEigenfactors(double t, const Workspace& ws, int refine, double tol, ApplyH&& applyH,
                           Eigen::Ref<Eigen::VectorXd> udot, Eigen::VectorXd& r, Eigen::VectorXd& du) {
  applyH(ws.B, udot);
  double residual = 0;
  if (!refineResidual(ws.A, ws.B, refine, applyH, udot, r, du, &residual))
    return Status::failure(t, Failure::RefinementDiverged, refineDivergedCause(refine));
  if (!(residual <= tol))
    return Status::failure(t, Failure::RefinementNotConverged, refineNotConvergedCause(refine, residual, tol));
  return {};
}

/// The paper's Jacobi correction (docs/theory.md §7, eq. (J)) of (C, lambda)
/// against A after an accepted step at t, its statistics in `info`; the
/// jacobi-not-converged failure, with how far C is from diagonalizing A.
Status jacobiCorrectAt(double t, const Eigen::MatrixXd& A, Eigen::Ref<RowMatrix> C, Eigen::Ref<Eigen::VectorXd> lambda,
                       CorrectionScratch& w, const MethodOptions& opt, StepInfo& info);

}  // namespace em
