#pragma once
/// An ODE y' = f(t, y) solved by SUNDIALS CVODE: variable-order (1 to 5) BDF,
/// Newton with dense direct solves and a difference-quotient Jacobian. It
/// lives in libeigenmass_dae beside IDA, for the same reason (solver/dae.hpp).
#include <functional>
#include <memory>
#include <string>

namespace em {

class BdfSolver {
 public:
  /// f(t, y, dydt): 0 on success, > 0 where it failed at a trial state (CVODE
  /// then cuts its step), < 0 to end the run.
  using Rhs = std::function<int(double t, const double* y, double* dydt)>;
  /// n unknowns from y0 at t = 0; rtol = atol = tol; max_step 0: CVODE's own
  /// bound; it never steps past t_stop.
  BdfSolver(int n, Rhs rhs, const double* y0, double tol, double max_step, double t_stop);
  ~BdfSolver();
  BdfSolver(const BdfSolver&) = delete;
  BdfSolver& operator=(const BdfSolver&) = delete;

  /// One of CVODE's own steps (its length its error test's); false on
  /// CVODE's failure, its message in error().
  bool step();
  /// y at t within the last step, from CVODE's interpolating polynomial (no evaluation).
  bool interpolate(double t, double* y) const;
  double t() const;
  const double* y() const;
  const std::string& error() const;
  long steps() const;
  long rhsEvaluations() const;  ///< its own and its Jacobian's

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace em
