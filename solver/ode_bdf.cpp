// SUNDIALS CVODE behind BdfSolver (solver/ode_bdf.hpp): nothing of eigenmass here.
#include "solver/ode_bdf.hpp"

#include <cvode/cvode.h>

#include "solver/sundials_dense.hpp"

namespace em {

namespace {

const sundials::SolverCalls kCvode = {"CVODE", CVodeSetUserData, CVodeSetErrHandlerFn, CVodeSetMaxNumSteps, CVodeSetMaxStep,
                                      CVodeSetLinearSolver};

}  // namespace

struct BdfSolver::Impl {
  sundials::Dense sun{kCvode};  // first: destroyed last
  Rhs rhs;
  int n = 0;
  void* mem = nullptr;
  N_Vector y = nullptr, dky = nullptr;
  double t = 0;

  ~Impl() {
    if (mem) CVodeFree(&mem);
    for (N_Vector x : {y, dky})
      if (x) N_VDestroy(x);
  }
};

namespace {

int rhsFn(double t, N_Vector y, N_Vector ydot, void* data) {
  auto* s = static_cast<BdfSolver::Impl*>(data);
  return s->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
}

}  // namespace

BdfSolver::BdfSolver(int n, Rhs rhs, const double* y0, double tol, double max_step, double t_stop)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.rhs = std::move(rhs);
  s.n = n;
  const SUNContext ctx = s.sun.ctx;
  const auto require = [&](bool ok, const char* what) { s.sun.require(ok, what); };
  s.y = N_VNew_Serial(n, ctx), s.dky = N_VNew_Serial(n, ctx);
  require(s.y && s.dky, "cannot allocate its vectors");
  for (int i = 0; i < n; ++i) N_VGetArrayPointer(s.y)[i] = y0[i];
  s.mem = CVodeCreate(CV_BDF, ctx);
  require(s.mem && CVodeInit(s.mem, rhsFn, 0.0, s.y) == CV_SUCCESS, "CVodeInit failed");
  s.sun.attach(s.mem, &s);
  require(CVodeSStolerances(s.mem, tol, tol) == CV_SUCCESS, "bad tolerance");
  CVodeSetStopTime(s.mem, t_stop);
  s.sun.finish(s.mem, s.y, n, max_step);
}

BdfSolver::~BdfSolver() = default;

bool BdfSolver::step() {
  Impl& s = *impl_;
  double t = s.t;
  // CV_ONE_STEP: tout only orients the first step; the stop time bounds every one.
  const int flag = CVode(s.mem, s.t + 1.0, s.y, &t, CV_ONE_STEP);
  s.t = t;
  s.sun.failed(flag);
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
const std::string& BdfSolver::error() const { return impl_->sun.error; }

long BdfSolver::steps() const { return sundials::count(CVodeGetNumSteps, impl_->mem); }

long BdfSolver::rhsEvaluations() const {  // its own and its Jacobian's
  return sundials::count(CVodeGetNumRhsEvals, impl_->mem) + sundials::count(CVodeGetNumLinRhsEvals, impl_->mem);
}

}  // namespace em
