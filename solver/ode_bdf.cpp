// SUNDIALS CVODE behind BdfSolver (solver/ode_bdf.hpp): nothing of eigenmass here.
#include "solver/ode_bdf.hpp"

#include <stdexcept>

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

namespace em {

struct BdfSolver::Impl {
  Rhs rhs;
  int n = 0;
  SUNContext ctx = nullptr;
  void* mem = nullptr;
  N_Vector y = nullptr, dky = nullptr;
  SUNMatrix J = nullptr;
  SUNLinearSolver LS = nullptr;
  double t = 0;
  std::string error;

  ~Impl() {
    if (mem) CVodeFree(&mem);
    if (LS) SUNLinSolFree(LS);
    if (J) SUNMatDestroy(J);
    for (N_Vector x : {y, dky})
      if (x) N_VDestroy(x);
    if (ctx) SUNContext_Free(&ctx);
  }
};

namespace {

int rhsFn(double t, N_Vector y, N_Vector ydot, void* data) {
  auto* s = static_cast<BdfSolver::Impl*>(data);
  return s->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
}

void errorFn(int, const char*, const char* function, char* msg, void* data) {
  static_cast<BdfSolver::Impl*>(data)->error = std::string(function) + ": " + msg;
}

void require(bool ok, const char* what) {
  if (!ok) throw std::runtime_error(std::string("CVODE: ") + what);
}

}  // namespace

BdfSolver::BdfSolver(int n, Rhs rhs, const double* y0, double tol, double max_step, double t_stop)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.rhs = std::move(rhs);
  s.n = n;
  require(SUNContext_Create(nullptr, &s.ctx) == 0, "cannot create a SUNDIALS context");
  s.y = N_VNew_Serial(n, s.ctx), s.dky = N_VNew_Serial(n, s.ctx);
  require(s.y && s.dky, "cannot allocate its vectors");
  for (int i = 0; i < n; ++i) N_VGetArrayPointer(s.y)[i] = y0[i];
  s.mem = CVodeCreate(CV_BDF, s.ctx);
  require(s.mem && CVodeInit(s.mem, rhsFn, 0.0, s.y) == CV_SUCCESS, "CVodeInit failed");
  CVodeSetUserData(s.mem, &s);
  CVodeSetErrHandlerFn(s.mem, errorFn, &s);
  require(CVodeSStolerances(s.mem, tol, tol) == CV_SUCCESS, "bad tolerance");
  CVodeSetMaxNumSteps(s.mem, 1000000);
  if (max_step > 0) CVodeSetMaxStep(s.mem, max_step);
  CVodeSetStopTime(s.mem, t_stop);
  s.J = SUNDenseMatrix(n, n, s.ctx);
  s.LS = s.J ? SUNLinSol_Dense(s.y, s.J, s.ctx) : nullptr;
  require(s.LS && CVodeSetLinearSolver(s.mem, s.LS, s.J) == CV_SUCCESS, "cannot attach the dense solver");
}

BdfSolver::~BdfSolver() = default;

bool BdfSolver::step() {
  Impl& s = *impl_;
  double t = s.t;
  // CV_ONE_STEP: tout only orients the first step; the stop time bounds every one.
  const int flag = CVode(s.mem, s.t + 1.0, s.y, &t, CV_ONE_STEP);
  s.t = t;
  if (flag < 0 && s.error.empty()) s.error = "flag " + std::to_string(flag);
  return flag >= 0;
}

bool BdfSolver::interpolate(double t, double* y) const {
  const Impl& s = *impl_;
  if (CVodeGetDky(s.mem, t, 0, s.dky) != CV_SUCCESS) return false;
  const double* d = N_VGetArrayPointer(s.dky);
  for (int i = 0; i < s.n; ++i) y[i] = d[i];
  return true;
}

double BdfSolver::t() const { return impl_->t; }
const double* BdfSolver::y() const { return N_VGetArrayPointer(impl_->y); }
const std::string& BdfSolver::error() const { return impl_->error; }

long BdfSolver::steps() const {
  long n = 0;
  CVodeGetNumSteps(impl_->mem, &n);
  return n;
}

long BdfSolver::rhsEvaluations() const {
  long own = 0, jac = 0;
  CVodeGetNumRhsEvals(impl_->mem, &own);
  CVodeGetNumLinRhsEvals(impl_->mem, &jac);
  return own + jac;
}

}  // namespace em
