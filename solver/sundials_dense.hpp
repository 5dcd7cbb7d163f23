#pragma once
// What SUNDIALS' IDA (solver/dae.cpp) and CVODE (solver/ode_bdf.cpp) are set up
// with alike: a context, the dense Jacobian and direct solver, an error line
// kept for the caller, and the same step bounds. Private to libeigenmass_dae:
// include it from those two files only (SUNDIALS' symbols stay inside that
// library, solver/dae.hpp says why).
#include <stdexcept>
#include <string>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

namespace em::sundials {

/// A counter of the solver's (IDAGetNumSteps, CVodeGetNumRhsEvals, ...).
inline long count(int (*get)(void* mem, long* n), void* mem) {
  long n = 0;
  get(mem, &n);
  return n;
}

/// The calls IDA and CVODE name differently but take alike (IDASetUserData,
/// CVodeSetUserData, ...): one solver's row.
struct SolverCalls {
  const char* name;  ///< its errors' prefix ("IDA")
  int (*set_user_data)(void* mem, void* data);
  int (*set_err_handler)(void* mem, void (*fn)(int, const char*, const char*, char*, void*), void* data);
  int (*set_max_num_steps)(void* mem, long steps);
  int (*set_max_step)(void* mem, double h);
  int (*set_linear_solver)(void* mem, SUNLinearSolver LS, SUNMatrix J);
};

/// The context, the dense solver and the last error of one solver's run. A
/// member declared before the solver's memory and vectors: it is destroyed
/// after them, the context last.
struct Dense {
  const SolverCalls& calls;
  SUNContext ctx = nullptr;
  SUNMatrix J = nullptr;
  SUNLinearSolver LS = nullptr;
  std::string error;  ///< the solver's last message ("IDASolve: ..."), or "flag N"

  explicit Dense(const SolverCalls& c) : calls(c) { require(SUNContext_Create(nullptr, &ctx) == 0, "cannot create a SUNDIALS context"); }
  ~Dense() {
    if (LS) SUNLinSolFree(LS);
    if (J) SUNMatDestroy(J);
    if (ctx) SUNContext_Free(&ctx);
  }
  Dense(const Dense&) = delete;
  Dense& operator=(const Dense&) = delete;

  /// Throws std::runtime_error "<solver>: what" unless ok.
  void require(bool ok, const char* what) const {
    if (!ok) throw std::runtime_error(std::string(calls.name) + ": " + what);
  }

  /// After the solver's Init: its user data, and its messages into `error`.
  void attach(void* mem, void* user_data) {
    calls.set_user_data(mem, user_data);
    calls.set_err_handler(mem, errorFn, this);
  }

  /// Last: up to a million steps, at most max_step each (0: the solver's own
  /// bound), and the dense direct solver on the Jacobian of n unknowns like `y`.
  void finish(void* mem, N_Vector y, int n, double max_step) {
    calls.set_max_num_steps(mem, 1000000);
    if (max_step > 0) calls.set_max_step(mem, max_step);
    J = SUNDenseMatrix(n, n, ctx);
    LS = J ? SUNLinSol_Dense(y, J, ctx) : nullptr;
    require(LS && calls.set_linear_solver(mem, LS, J) == 0, "cannot attach the dense solver");
  }

  /// A failed call's flag, unless the solver said more.
  void failed(int flag) {
    if (flag < 0 && error.empty()) error = "flag " + std::to_string(flag);
  }

 private:
  static void errorFn(int, const char*, const char* function, char* msg, void* data) {
    static_cast<Dense*>(data)->error = std::string(function) + ": " + msg;
  }
};

}  // namespace em::sundials
