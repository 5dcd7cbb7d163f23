#include "solver/integrate.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <memory>
#include <stdexcept>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

namespace em {

namespace {

const std::pair<Integrator, const char*> kIntegrators[] = {
    {Integrator::RK4, "rk4"}, {Integrator::RKF45, "rkf45"}, {Integrator::RK8PD, "rk8pd"}, {Integrator::BSIMP, "bsimp"}};

double cpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// What GSL's callbacks get: the dynamics and the Jacobian's scratch (sized once per run).
struct GslParams {
  explicit GslParams(Dynamics& d) : dyn(&d), yp(d.size()), f0(d.size()), f1(d.size()) {}
  Dynamics* dyn;
  std::vector<double> yp, f0, f1;
};

int gslRhs(double t, const double y[], double dydt[], void* params) {
  return static_cast<GslParams*>(params)->dyn->rhs(t, y, dydt) ? GSL_SUCCESS : GSL_EBADFUNC;
}

// bsimp needs df/dy: a forward finite difference of the right-hand side
// (the system is autonomous, df/dt = 0).
int gslJacobian(double t, const double y[], double* dfdy, double dfdt[], void* params) {
  auto& p = *static_cast<GslParams*>(params);
  Dynamics* dyn = p.dyn;
  const int n = dyn->size();
  std::vector<double>&yp = p.yp, &f0 = p.f0, &f1 = p.f1;
  std::copy(y, y + n, yp.begin());
  if (!dyn->rhs(t, y, f0.data())) return GSL_EBADFUNC;
  for (int j = 0; j < n; ++j) {
    const double h = 1.4901161193847656e-08 * std::max(1.0, std::abs(y[j]));
    yp[j] = y[j] + h;
    if (!dyn->rhs(t, yp.data(), f1.data())) return GSL_EBADFUNC;
    yp[j] = y[j];
    for (int i = 0; i < n; ++i) dfdy[i * n + j] = (f1[i] - f0[i]) / h;
  }
  for (int i = 0; i < n; ++i) dfdt[i] = 0;
  return GSL_SUCCESS;
}

// Fixed step: exact multiples of dt, output every `per_output` steps.
void runFixed(Dynamics& dyn, const SimOptions& opt, int n_out, int per_output, Eigen::VectorXd& y, Trajectory& tr) {
  const int n = dyn.size();
  Eigen::VectorXd k1(n), k2(n), k3(n), k4(n), tmp(n);
  auto f = [&dyn](double t, const double* yy, double* dy) { return dyn.rhs(t, yy, dy); };
  for (int k = 1; k <= n_out; ++k) {
    for (int s = 0; s < per_output; ++s) {
      const long step = static_cast<long>(k - 1) * per_output + s;
      const double t = step * opt.dt;
      if (!rk4Step(f, t, opt.dt, y.data(), n, k1.data(), k2.data(), k3.data(), k4.data(), tmp.data())) return;
      ++tr.steps;
      if (!dyn.postStep(t + opt.dt, y.data())) return;
    }
    appendSample(dyn, k * opt.output_dt, y.data(), opt.diagnostics, tr);
  }
}

struct GslDeleter {
  void operator()(gsl_odeiv2_step* s) const { gsl_odeiv2_step_free(s); }
  void operator()(gsl_odeiv2_control* c) const { gsl_odeiv2_control_free(c); }
  void operator()(gsl_odeiv2_evolve* e) const { gsl_odeiv2_evolve_free(e); }
};

// Adaptive: GSL's evolve loop; the method's correction runs after every
// accepted step, and the stepper is reset so it sees the corrected state.
void runAdaptive(Dynamics& dyn, const SimOptions& opt, int n_out, Eigen::VectorXd& y, Trajectory& tr) {
  const int n = dyn.size();
  const gsl_odeiv2_step_type* type = opt.integrator == Integrator::RKF45   ? gsl_odeiv2_step_rkf45
                                     : opt.integrator == Integrator::RK8PD ? gsl_odeiv2_step_rk8pd
                                                                           : gsl_odeiv2_step_bsimp;
  std::unique_ptr<gsl_odeiv2_step, GslDeleter> step(gsl_odeiv2_step_alloc(type, n));
  std::unique_ptr<gsl_odeiv2_control, GslDeleter> ctl(gsl_odeiv2_control_standard_new(opt.tol, opt.tol, 1.0, 0.0));
  std::unique_ptr<gsl_odeiv2_evolve, GslDeleter> evo(gsl_odeiv2_evolve_alloc(n));
  GslParams params(dyn);
  gsl_odeiv2_system sys{gslRhs, gslJacobian, static_cast<size_t>(n), &params};
  double t = 0, h = std::min(1e-3, opt.output_dt);
  const bool corrects = dyn.method() == Method::EigenJacobi || dyn.method() == Method::EigenJacobiOrth;
  for (int k = 1; k <= n_out; ++k) {
    const double t_out = k * opt.output_dt;
    while (t < t_out) {
      const int status = gsl_odeiv2_evolve_apply(evo.get(), ctl.get(), step.get(), &sys, &t, t_out, &h, y.data());
      if (status != GSL_SUCCESS) {
        dyn.fail(t, std::string("integrator stopped: ") + gsl_strerror(status));
        return;
      }
      ++tr.steps;
      if (!dyn.postStep(t, y.data())) return;
      if (corrects) gsl_odeiv2_step_reset(step.get());
      if (h < 1e-14 * std::max(1.0, t)) {
        dyn.fail(t, "step size underflow (h = " + std::to_string(h) + ")");
        return;
      }
    }
    appendSample(dyn, t_out, y.data(), opt.diagnostics, tr);
  }
}

}  // namespace

const char* integratorName(Integrator i) {
  for (auto& [k, name] : kIntegrators)
    if (k == i) return name;
  return "?";
}

bool parseIntegrator(const std::string& s, Integrator& i) {
  for (auto& [k, name] : kIntegrators)
    if (s == name) { i = k; return true; }
  return false;
}

bool isFixedStep(Integrator i) { return i == Integrator::RK4; }

void appendSample(Dynamics& dyn, double t, const double* y, bool diagnostics, Trajectory& tr) {
  const double c0 = cpuSeconds();  // sampling is bookkeeping, not integration: timed apart
  const Model& m = dyn.model();
  const double energy = dyn.energyAt(y);  // also refreshes the kinematics for the poses
  const Workspace& ws = dyn.workspace();
  Eigen::VectorXd qf, uf;
  m.qToFile(Eigen::Map<const Eigen::VectorXd>(y, m.nq), qf);
  m.uToFile(Eigen::Map<const Eigen::VectorXd>(y + m.nq, m.nu), uf);
  std::vector<Pose> poses(m.n());
  for (int i = 0; i < m.n(); ++i) poses[m.bodies[i].file_index] = {ws.r[i], matrixToQuat(ws.R[i])};
  tr.t.push_back(t);
  tr.q.push_back(qf);
  tr.u.push_back(uf);
  tr.energy.push_back(energy);
  tr.kinetic.push_back(ws.kinetic);
  tr.poses.push_back(std::move(poses));
  if (diagnostics && dyn.eigenfactor()) {
    const EigenDiagnostics d = dyn.diagnosticsAt(y);
    tr.diag.push_back({d.orth_err, d.offdiag_rel, d.min_gap, d.max_Omega, d.inv_err});
  }
  tr.sample_time_s += cpuSeconds() - c0;
}

Trajectory simulate(const Model& m, Method method, const SimOptions& opt, const MethodOptions& mopt) {
  if (!(opt.t_end > 0) || !(opt.output_dt > 0)) throw std::invalid_argument("t_end and output_dt must be > 0");
  const double ratio = opt.t_end / opt.output_dt;
  const int n_out = static_cast<int>(std::llround(ratio));
  if (std::abs(ratio - n_out) > 1e-9 * ratio) throw std::invalid_argument("t_end must be a whole multiple of output_dt");
  int per_output = 1;
  if (isFixedStep(opt.integrator)) {
    if (!(opt.dt > 0)) throw std::invalid_argument("dt must be > 0");
    const double r = opt.output_dt / opt.dt;
    per_output = static_cast<int>(std::llround(r));
    if (per_output < 1 || std::abs(r - per_output) > 1e-9 * r)
      throw std::invalid_argument("output_dt must be a whole multiple of dt");
  } else if (!(opt.tol > 0)) {
    throw std::invalid_argument("tol must be > 0");
  }
  Trajectory tr = makeTrajectory(m, methodName(method), integratorName(opt.integrator));
  Dynamics dyn(m, method, mopt);
  Eigen::VectorXd y = dyn.initialState(m.q0(), m.u0());
  appendSample(dyn, 0.0, y.data(), opt.diagnostics, tr);
  tr.sample_time_s = 0;
  gsl_error_handler_t* old = gsl_set_error_handler_off();  // GSL errors become statuses, never aborts
  const double c0 = cpuSeconds();
  if (isFixedStep(opt.integrator))
    runFixed(dyn, opt, n_out, per_output, y, tr);
  else
    runAdaptive(dyn, opt, n_out, y, tr);
  tr.run_time_s = cpuSeconds() - c0 - tr.sample_time_s;
  gsl_set_error_handler(old);
  tr.rhs_evals = dyn.rhs_evals;
  if (dyn.eigenfactor()) tr.eigen = dyn.stats;
  if (dyn.failure().failed) {
    tr.status = "failed";
    tr.failure = dyn.failure().cause;
    tr.failure_time = dyn.failure().t;
  }
  return tr;
}

}  // namespace em
