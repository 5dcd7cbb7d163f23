#pragma once
/// A DAE F(t, y, y') = 0 solved by SUNDIALS IDA (variable-order BDF, dense
/// direct solves, difference-quotient Jacobian). It lives in its own shared
/// library, libeigenmass_dae, linked with SUNDIALS' static archives whose
/// symbols stay inside it: Simbody's libSimTKmath exports an old SUNDIALS'
/// N_Vector functions, and a process that loads both would otherwise call
/// Simbody's with IDA 6.4's vectors (a crash in N_VGetLength, measured).
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace em {

class DaeSolver {
 public:
  /// F(t, y, yp, F); returns false where it cannot be evaluated (IDA then cuts its step).
  using Residual = std::function<bool(double t, const double* y, const double* yp, double* F)>;
  /// n unknowns; differential[i] false for an algebraic one (kept out of the
  /// error test: index 2); y0, yp0 consistent at t = 0; rtol = atol = tol;
  /// max_step 0: IDA's own bound; it never steps past t_stop (the run's end).
  DaeSolver(int n, Residual residual, const std::vector<bool>& differential, const double* y0, const double* yp0, double tol,
            double max_step, double t_stop);
  ~DaeSolver();
  DaeSolver(const DaeSolver&) = delete;
  DaeSolver& operator=(const DaeSolver&) = delete;

  /// y and y' at t_out: IDA steps as its error test lets it (past t_out, up
  /// to t_stop) and interpolates there (IDA_NORMAL), as CVODE's route samples
  /// its own polynomial; it is not stopped at every output (that cost A04 nine
  /// times the residuals: issue 76). False on IDA's failure, its message in error().
  bool advance(double t_out);
  double t() const;
  const double* y() const;
  const std::string& error() const;
  long steps() const;
  long residualEvaluations() const;  ///< its own and its Jacobian's

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace em
