// SUNDIALS IDA behind DaeSolver (solver/dae.hpp): nothing of eigenmass here.
#include "solver/dae.hpp"

#include <stdexcept>

#include <ida/ida.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

namespace em {

struct DaeSolver::Impl {
  Residual residual;
  int n = 0;
  SUNContext ctx = nullptr;
  void* mem = nullptr;
  N_Vector yy = nullptr, yp = nullptr, id = nullptr;
  SUNMatrix J = nullptr;
  SUNLinearSolver LS = nullptr;
  double t = 0;
  std::string error;

  ~Impl() {
    if (mem) IDAFree(&mem);
    if (LS) SUNLinSolFree(LS);
    if (J) SUNMatDestroy(J);
    for (N_Vector x : {yy, yp, id})
      if (x) N_VDestroy(x);
    if (ctx) SUNContext_Free(&ctx);
  }
};

namespace {

constexpr double kAlgebraicAtol = 1e10;

int residualFn(double t, N_Vector yy, N_Vector yp, N_Vector rr, void* data) {
  auto* s = static_cast<DaeSolver::Impl*>(data);
  return s->residual(t, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp), N_VGetArrayPointer(rr)) ? 0 : 1;  // 1: recoverable
}

void errorFn(int, const char*, const char* function, char* msg, void* data) {
  static_cast<DaeSolver::Impl*>(data)->error = std::string(function) + ": " + msg;
}

void require(bool ok, const char* what) {
  if (!ok) throw std::runtime_error(std::string("IDA: ") + what);
}

}  // namespace

DaeSolver::DaeSolver(int n, Residual residual, const std::vector<bool>& differential, const double* y0, const double* yp0,
                     double tol, double max_step)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.residual = std::move(residual);
  s.n = n;
  require(SUNContext_Create(nullptr, &s.ctx) == 0, "cannot create a SUNDIALS context");
  s.yy = N_VNew_Serial(n, s.ctx), s.yp = N_VNew_Serial(n, s.ctx), s.id = N_VNew_Serial(n, s.ctx);
  require(s.yy && s.yp && s.id, "cannot allocate its vectors");
  for (int i = 0; i < n; ++i) {
    N_VGetArrayPointer(s.yy)[i] = y0[i];
    N_VGetArrayPointer(s.yp)[i] = yp0[i];
    N_VGetArrayPointer(s.id)[i] = differential[i] ? 1.0 : 0.0;
  }
  s.mem = IDACreate(s.ctx);
  require(s.mem && IDAInit(s.mem, residualFn, 0.0, s.yy, s.yp) == IDA_SUCCESS, "IDAInit failed");
  IDASetUserData(s.mem, &s);
  IDASetErrHandlerFn(s.mem, errorFn, &s);
  // The algebraic unknowns (multipliers) are out of the error test
  // (suppressAlg) and, with an absolute tolerance this loose, out of the
  // Newton iteration's convergence test too: they follow from the
  // differential ones, and at the scale of a constraint force (1e4 N in
  // Andrews' mechanism) a tolerance meant for angles stalls the corrector.
  N_Vector atol = N_VNew_Serial(n, s.ctx);
  require(atol != nullptr, "cannot allocate its vectors");
  for (int i = 0; i < n; ++i) N_VGetArrayPointer(atol)[i] = differential[i] ? tol : kAlgebraicAtol;
  const int flag = IDASVtolerances(s.mem, tol, atol);
  N_VDestroy(atol);
  require(flag == IDA_SUCCESS, "bad tolerance");
  IDASetId(s.mem, s.id);
  IDASetSuppressAlg(s.mem, SUNTRUE);
  IDASetMaxNumSteps(s.mem, 1000000);
  if (max_step > 0) IDASetMaxStep(s.mem, max_step);
  s.J = SUNDenseMatrix(n, n, s.ctx);
  s.LS = s.J ? SUNLinSol_Dense(s.yy, s.J, s.ctx) : nullptr;
  require(s.LS && IDASetLinearSolver(s.mem, s.LS, s.J) == IDA_SUCCESS, "cannot attach the dense solver");
}

DaeSolver::~DaeSolver() = default;

bool DaeSolver::advance(double t_out) {
  Impl& s = *impl_;
  IDASetStopTime(s.mem, t_out);
  double t = s.t;
  const int flag = IDASolve(s.mem, t_out, &t, s.yy, s.yp, IDA_NORMAL);
  s.t = t;
  if (flag < 0 && s.error.empty()) s.error = "flag " + std::to_string(flag);
  return flag >= 0;
}

double DaeSolver::t() const { return impl_->t; }
const double* DaeSolver::y() const { return N_VGetArrayPointer(impl_->yy); }
const std::string& DaeSolver::error() const { return impl_->error; }

long DaeSolver::steps() const {
  long n = 0;
  IDAGetNumSteps(impl_->mem, &n);
  return n;
}

long DaeSolver::residualEvaluations() const {
  long own = 0, jac = 0;
  IDAGetNumResEvals(impl_->mem, &own);
  IDAGetNumLinResEvals(impl_->mem, &jac);
  return own + jac;
}

}  // namespace em
