#pragma once
/// A method's own code (docs/theory.md §8): the extra state it integrates
/// beside (q, u), how it gets u' from the formed equations, and what it does
/// after an accepted step. The registry's row builds it; Dynamics drives it.
#include <limits>
#include <memory>
#include <string>

#include "solver/eigenfactor.hpp"
#include "solver/formation.hpp"
#include "solver/run.hpp"

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

class Formulation {
 public:
  virtual ~Formulation() = default;
  /// State entries beyond (q, u).
  virtual int extraSize() const { return 0; }
  /// Whether the evaluation needs A' formed (the eigenfactor rates do).
  virtual bool needsAdot() const { return false; }
  /// The extra state at t = 0 from the formed A.  // x: (extraSize)
  virtual void initialize(const Workspace&, double* /*x*/) {}
  /// u' and the extra state's rates from the formed A, B (and A').  // udot: (nu), xdot: (extraSize)
  virtual Status rates(double t, const Workspace& ws, const double* x, double* udot, double* xdot, EvalInfo& info) = 0;
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

/// The registry's factories (solver/classical.cpp, solver/eigen_method.cpp).
std::unique_ptr<Formulation> makeClassical(const Model& m, const MethodInfo& row, const MethodOptions& opt);
std::unique_ptr<Formulation> makeEigenfactor(const Model& m, const MethodInfo& row, const MethodOptions& opt);
std::unique_ptr<Formulation> makeEigenBlock(const Model& m, const MethodInfo& row, const MethodOptions& opt);

}  // namespace em
