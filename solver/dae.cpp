// SUNDIALS IDA behind DaeSolver (solver/dae.hpp): nothing of eigenmass here.
#include "solver/dae.hpp"

#include <ida/ida.h>

#include "solver/sundials_dense.hpp"

namespace em {

namespace {

const sundials::SolverCalls kIda = {"IDA", IDASetUserData, IDASetErrHandlerFn, IDASetMaxNumSteps, IDASetMaxStep, IDASetLinearSolver};

}  // namespace

struct DaeSolver::Impl {
  sundials::Dense sun{kIda};  // first: destroyed last
  Residual residual;
  int n = 0;
  void* mem = nullptr;
  N_Vector yy = nullptr, yp = nullptr, id = nullptr;
  double t = 0;

  ~Impl() {
    if (mem) IDAFree(&mem);
    for (N_Vector x : {yy, yp, id})
      if (x) N_VDestroy(x);
  }
};

namespace {

constexpr double kAlgebraicAtol = 1e10;

int residualFn(double t, N_Vector yy, N_Vector yp, N_Vector rr, void* data) {
  auto* s = static_cast<DaeSolver::Impl*>(data);
  return s->residual(t, N_VGetArrayPointer(yy), N_VGetArrayPointer(yp), N_VGetArrayPointer(rr)) ? 0 : 1;  // 1: recoverable
}

}  // namespace

DaeSolver::DaeSolver(int n, Residual residual, const std::vector<bool>& differential, const double* y0, const double* yp0,
                     double tol, double max_step, double t_stop)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.residual = std::move(residual);
  s.n = n;
  const SUNContext ctx = s.sun.ctx;
  const auto require = [&](bool ok, const char* what) { s.sun.require(ok, what); };
  s.yy = N_VNew_Serial(n, ctx), s.yp = N_VNew_Serial(n, ctx), s.id = N_VNew_Serial(n, ctx);
  require(s.yy && s.yp && s.id, "cannot allocate its vectors");
  for (int i = 0; i < n; ++i) {
    N_VGetArrayPointer(s.yy)[i] = y0[i];
    N_VGetArrayPointer(s.yp)[i] = yp0[i];
    N_VGetArrayPointer(s.id)[i] = differential[i] ? 1.0 : 0.0;
  }
  s.mem = IDACreate(ctx);
  require(s.mem && IDAInit(s.mem, residualFn, 0.0, s.yy, s.yp) == IDA_SUCCESS, "IDAInit failed");
  s.sun.attach(s.mem, &s);
  // The algebraic unknowns (multipliers) are out of the error test
  // (suppressAlg) and, with an absolute tolerance this loose, out of the
  // Newton iteration's convergence test too: they follow from the
  // differential ones, and at the scale of a constraint force (1e4 N in
  // Andrews' mechanism) a tolerance meant for angles stalls the corrector.
  N_Vector atol = N_VNew_Serial(n, ctx);
  require(atol != nullptr, "cannot allocate its vectors");
  for (int i = 0; i < n; ++i) N_VGetArrayPointer(atol)[i] = differential[i] ? tol : kAlgebraicAtol;
  const int flag = IDASVtolerances(s.mem, tol, atol);
  N_VDestroy(atol);
  require(flag == IDA_SUCCESS, "bad tolerance");
  IDASetId(s.mem, s.id);
  IDASetSuppressAlg(s.mem, SUNTRUE);
  IDASetStopTime(s.mem, t_stop);
  s.sun.finish(s.mem, s.yy, n, max_step);
}

DaeSolver::~DaeSolver() = default;

bool DaeSolver::advance(double t_out) {
  Impl& s = *impl_;
  double t = s.t;
  const int flag = IDASolve(s.mem, t_out, &t, s.yy, s.yp, IDA_NORMAL);
  s.t = t;
  s.sun.failed(flag);
  return flag >= 0;
}

double DaeSolver::t() const { return impl_->t; }
const double* DaeSolver::y() const { return N_VGetArrayPointer(impl_->yy); }
const std::string& DaeSolver::error() const { return impl_->sun.error; }

long DaeSolver::steps() const { return sundials::count(IDAGetNumSteps, impl_->mem); }

long DaeSolver::residualEvaluations() const {  // its own and its Jacobian's
  return sundials::count(IDAGetNumResEvals, impl_->mem) + sundials::count(IDAGetNumLinResEvals, impl_->mem);
}

}  // namespace em
