#pragma once
/// SUNDIALS IDA on a mechanism's stabilized index-2 form (Gear, Gupta and
/// Leimkuhler; docs/theory.md §15, eqs. (M10)): the reference of scenes with
/// loops. Its unknowns are Y = [q, u, lambda, mu, W_diss]:
///   q' = qdot(q, u - G^T mu),  A u' = B + G^T lambda,  G u = 0,  g(q) = 0,
///   W_diss' = the non-conservative power,
/// on the independent rows of G, chosen once at the initial state by a
/// column-pivoted QR of G^T (a planar mechanism closed by balls has
/// redundant rows; IDA's Newton matrix must not be singular). IDA's own
/// variable-order BDF, its dense direct solver and its difference-quotient
/// Jacobian do the rest; lambda and mu are kept out of its error test.
#include <memory>
#include <string>

#include "solver/dae.hpp"
#include "solver/formation.hpp"
#include "solver/method.hpp"

namespace em {

class IdaRun {
 public:
  /// At the model's consistent initial state (q0, u0); u'(0) and lambda(0)
  /// from the constrained equations. rtol = atol = tol.
  IdaRun(const Model& m, double tol, double max_step, double t_stop);
  ~IdaRun();
  IdaRun(const IdaRun&) = delete;
  IdaRun& operator=(const IdaRun&) = delete;

  /// The state at t_out, from IDA's interpolant (DaeSolver::advance); a failure carries IDA's own message.
  Status advance(double t_out);
  /// q, u (internal order) and W_diss at the last time reached, into y laid
  /// out as Dynamics does for a method without extra state.
  void state(double* y) const;
  long steps() const;
  long residualEvaluations() const;
  /// The rank of G at the initial state: the rows IDA integrates.
  int rank() const { return rank_; }

  struct Impl;  ///< the residual's workspace (solver/ida.cpp)

 private:
  std::unique_ptr<Impl> impl_;
  std::unique_ptr<DaeSolver> dae_;
  int rank_ = 0;
};

}  // namespace em
