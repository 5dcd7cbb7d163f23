#include "solver/integrate.hpp"

#include "solver/mechanism/formulation.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <memory>
#include <stdexcept>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "solver/limits.hpp"

#include "solver/augmented_lagrangian.hpp"
#include "solver/ida.hpp"
#include "solver/ode_bdf.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

double cpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// One integration's own state: the dynamics it drives, its counters and its first
// failure; the trajectory receives them as they happen (steps) or at the end.
class Integration {
 public:
  Integration(Dynamics& dyn, const RunSpec& spec, Trajectory& tr, const SampleObserver& observe)
      : dyn_(dyn), spec_(spec), tr_(tr), observe_(observe), poses_(dyn.model().n()), limits_(dyn.model()),
        y0_(dyn.size()), yt_(dyn.size()), free_(dyn.size()) {
    stats_.min_gap = std::numeric_limits<double>::infinity();
  }

  // One right-hand-side evaluation, counted; a failure is recorded (as the
  // run's, or only as the step's when trial failures are retried).
  bool evaluate(double t, const double* y, double* dydt) {
    ++rhs_evals_;
    EvalInfo ev;
    const Status s = dyn_.rhs(t, y, dydt, &ev);
    if (!s) {
      if (retrying_) {
        if (trial_failure_.ok) trial_failure_ = s;
        return false;
      }
      return fail(s);
    }
    stats_.max_abs_Omega = std::max(stats_.max_abs_Omega, ev.max_Omega);
    if (limits_.anyHeld()) limits_.constrain(y, dydt);  // a coordinate resting on its stop
    return true;
  }

  bool limitsActive() const { return limits_.active(); }
  // A sampled controller's sample at t from y (theory.md §18): held until the next.
  void sampleControl(double t, const double* y) { dyn_.sampleControl(t, y); }
  bool limitsCrossed(const double* y) const { return limits_.beyond(y) >= 0; }

  // The stops a step from (t0, y0) to (t0 + h, y) crossed (docs/theory.md §17):
  // each crossing located on `advance(start, tau, out)` (the scheme's own step
  // of tau from the state at `start`) to kLimitTimeTol, the impact applied
  // there, the rest of the step taken from it. y0 is consumed. False on a failure.
  template <class Advance>
  bool limitEvents(double t0, double h, Eigen::VectorXd& y0, Eigen::VectorXd& y, Advance advance) {
    double start = t0, rem = h;
    for (int impacts = 0;; ++impacts) {
      int c = limits_.beyond(y.data());
      if (c < 0) break;
      if (impacts >= kImpactsPerStepMax)
        return fail(Status::failure(start, Failure::BlowUp, "more than " + std::to_string(kImpactsPerStepMax) +
                                                                  " impacts within one step (a stop hit without end)"));
      double a = 0, b = rem, ga = limits_.inside(y0.data(), static_cast<size_t>(c)), gb = limits_.inside(y.data(), static_cast<size_t>(c));
      yt_ = y;
      int last_side = 0;
      while (b - a > kLimitTimeTol) {  // Illinois: regula falsi that halves the stale end's weight
        double tau = b - gb * (b - a) / (gb - ga);
        if (!(tau > a && tau < b)) tau = 0.5 * (a + b);
        if (!advance(start, tau, y0, yt_)) return false;
        const int d = limits_.beyond(yt_.data());
        if (d >= 0 && d != c) c = d, ga = limits_.inside(y0.data(), static_cast<size_t>(c));  // another stop, earlier
        const double g = limits_.inside(yt_.data(), static_cast<size_t>(c));
        if (g < 0) {
          b = tau, gb = g;
          if (last_side == -1) ga *= 0.5;
          last_side = -1;
        } else {
          a = tau, ga = g;
          if (last_side == 1) gb *= 0.5;
          last_side = 1;
        }
      }
      if (!advance(start, b, y0, yt_)) return false;  // the state at the crossing (its coordinate then put on the stop)
      if (!freeUdot(start + b, yt_.data())) return false;
      limits_.impact(start + b, yt_.data(), c, free_.data() + dyn_.model().nq);
      start += b, rem -= b;
      y0 = yt_;
      y = yt_;
      if (rem > kLimitTimeTol && !advance(start, rem, y0, y)) return false;
    }
    if (limits_.anyHeld()) {  // a held coordinate whose contact force would pull is let go
      if (!freeUdot(t0 + h, y.data())) return false;
      limits_.release(y.data(), free_.data() + dyn_.model().nq);
    }
    return true;
  }

  // Adaptive runs: evaluation failures become the step's, to be retried.
  void retryTrialFailures(bool on) { retrying_ = on; }
  // The failed trial evaluation of the last step (ok if none), then forgotten.
  Status takeTrialFailure() {
    Status s = trial_failure_;
    trial_failure_ = Status();
    return s;
  }
  long& retries() { return tr_.step_retries; }
  long& gridCutSteps() { return tr_.grid_cut_steps; }

  // After an accepted step ending at t.
  bool accept(double t, double* y) {
    ++tr_.steps;
    StepInfo st;
    const Status s = dyn_.afterStep(t, y, st);
    if (st.corrected) {
      stats_.jacobi_sweeps += st.jacobi.sweeps;
      stats_.jacobi_rotations += st.jacobi.rotations;
      stats_.jacobi_single_sweep_steps += st.jacobi.sweeps <= 1;
      stats_.jacobi_max_sweeps = std::max(stats_.jacobi_max_sweeps, st.jacobi.sweeps);
    }
    stats_.block_merges += st.merges;
    stats_.block_splits += st.splits;
    if (!s) return fail(s);
    if (st.min_gap < stats_.min_gap) {
      stats_.min_gap = st.min_gap;
      stats_.min_gap_time = t;
    }
    return true;
  }

  bool fail(const Status& s) {
    if (failure_.ok) failure_ = s;  // keep the first cause
    return false;
  }

  // The sample at t; sampling is bookkeeping, not integration: timed apart.
  void sample(double t, const double* y) {
    const double c0 = cpuSeconds();
    const Model& m = dyn_.model();
    dyn_.kinematicsAt(y);
    const Workspace& ws = dyn_.workspace();
    for (int i = 0; i < m.n(); ++i) poses_[i] = {ws.r[i], matrixToQuat(ws.R[i])};
    if (!m.loops.empty()) dyn_.recordLoopsAt(y);  // after the poses: it re-forms the workspace at the same y
    appendSample(tr_, m, t, y, y + m.nq, poses_, {ws.energy(), ws.kinetic, dyn_.dissipated(y) + limits_.energyLost()});
    if (spec_.diagnostics && dyn_.eigenfactor()) {
      const EigenDiagnostics d = dyn_.diagnosticsAt(y);
      tr_.diag.push_back({d.orth_err, d.offdiag_rel, d.min_gap, d.max_Omega, d.inv_err});
    }
    if (observe_) observe_(t);
    tr_.sample_time_s += cpuSeconds() - c0;
  }

  // y: the state where the run ended (on a failure, the last accepted one or
  // the step that failed its check).
  void finish(const double* y) {
    tr_.rhs_evals = rhs_evals_;
    if (dyn_.eigenfactor()) tr_.eigen = stats_;
    tr_.has_loops = !dyn_.model().loops.empty();
    if (tr_.has_loops) tr_.loops = dyn_.loopStats();
    tr_.impacts = limits_.impacts();
    tr_.impact_count = limits_.impactCount();
    if (failure_.ok) return;
    markFailed(tr_, failure_.t, failure_.kind, failure_.cause);
    tr_.failure_cond_A = dyn_.conditionAt(y);
  }

  Dynamics& dynamics() { return dyn_; }
  void countEvaluations(long n) { rhs_evals_ += n; }

 private:
  // The free u' at y (no stop held) into free_, counted as an evaluation.
  bool freeUdot(double t, const double* y) {
    ++rhs_evals_;
    const Status st = dyn_.rhs(t, y, free_.data());
    return st ? true : fail(st);
  }
  static constexpr int kImpactsPerStepMax = 10000;
  Dynamics& dyn_;
  const RunSpec& spec_;
  Trajectory& tr_;
  const SampleObserver& observe_;
  std::vector<Pose> poses_;  // (n) internal order
  long rhs_evals_ = 0;
  EigenStats stats_;
  Status failure_;
  bool retrying_ = false;
  Status trial_failure_;
  JointLimitEvents limits_;
  Eigen::VectorXd y0_, yt_, free_;  // (n): a step's start, a located state, a free u'
};

// Fixed step: exact multiples of dt, output every `per_output` steps, each
// step by the integrator row's step function.
void runFixed(Integration& run, const RunSpec& spec, long n_out, long per_output, Eigen::VectorXd& y) {
  const int n = run.dynamics().size();
  const FixedStep step = info(spec.integrator).step;
  StepScratch w(n);
  auto evaluate = [&run](double t, const double* yy, double* dy) { return run.evaluate(t, yy, dy); };
  const Derivative f(evaluate);
  const bool limits = run.limitsActive();
  Eigen::VectorXd y0(limits ? n : 0);
  // The scheme's own step of tau from `from` at `start` into `out` (a stop's location, the rest of a step).
  auto advance = [&](double start, double tau, const Eigen::VectorXd& from, Eigen::VectorXd& out) {
    out = from;
    return step(f, start, tau, out.data(), n, w);
  };
  // A sampled controller is sampled at the starts of the steps on its instants (refuseControl: dt divides its period).
  const ControlLoop& control = run.dynamics().control();
  const long per_sample = control.sampled() ? stepsPerControlPeriod(control.period(), spec.dt) : 0;
  for (long k = 1; k <= n_out; ++k) {
    for (long s = 0; s < per_output; ++s) {
      const long i = (k - 1) * per_output + s;
      const double t = i * spec.dt;
      if (per_sample && i % per_sample == 0) run.sampleControl(t, y.data());
      if (limits) y0 = y;
      if (!step(f, t, spec.dt, y.data(), n, w)) return;
      if (limits && !run.limitEvents(t, spec.dt, y0, y, advance)) return;
      if (!run.accept(t + spec.dt, y.data())) return;
    }
    run.sample(k * spec.output_dt, y.data());
  }
}

// What GSL's callbacks get: the run and the Jacobian's scratch (sized once per run).
struct GslParams {
  GslParams(Integration& r, int n) : run(&r), yp(n), f0(n), f1(n) {}
  Integration* run;
  std::vector<double> yp, f0, f1;
};

int gslRhs(double t, const double y[], double dydt[], void* params) {
  return static_cast<GslParams*>(params)->run->evaluate(t, y, dydt) ? GSL_SUCCESS : GSL_EBADFUNC;
}

// bsimp needs df/dy: a forward finite difference of the right-hand side
// (the system is autonomous, df/dt = 0).
int gslJacobian(double t, const double y[], double* dfdy, double dfdt[], void* params) {
  auto& p = *static_cast<GslParams*>(params);
  const int n = static_cast<int>(p.yp.size());
  std::vector<double>&yp = p.yp, &f0 = p.f0, &f1 = p.f1;
  std::copy(y, y + n, yp.begin());
  if (!p.run->evaluate(t, y, f0.data())) return GSL_EBADFUNC;
  for (int j = 0; j < n; ++j) {
    const double h = 1.4901161193847656e-08 * std::max(1.0, std::abs(y[j]));
    yp[j] = y[j] + h;
    if (!p.run->evaluate(t, yp.data(), f1.data())) return GSL_EBADFUNC;
    yp[j] = y[j];
    for (int i = 0; i < n; ++i) dfdy[i * n + j] = (f1[i] - f0[i]) / h;
  }
  for (int i = 0; i < n; ++i) dfdt[i] = 0;
  return GSL_SUCCESS;
}

struct GslDeleter {
  void operator()(gsl_odeiv2_step* s) const { gsl_odeiv2_step_free(s); }
  void operator()(gsl_odeiv2_control* c) const { gsl_odeiv2_control_free(c); }
  void operator()(gsl_odeiv2_evolve* e) const { gsl_odeiv2_evolve_free(e); }
};

// Smallest adaptive step, relative to max(1, t): below it the run has stalled.
constexpr double kMinStepRel = 1e-14;
// Two instants (a control sample, an output) this close, relative to max(1, t), are one.
constexpr double kSameInstantRel = 1e-12;

// A trial stage of the step from t failed: shrink h fourfold, or end the run
// when it would fall below the smallest step (the trial's cause kept). A
// failure at the step's start is the run's own.
bool retrySmaller(Integration& run, const Status& trial, double t, double& h) {
  if (trial.t == t) {  // the step's own start, an accepted state: no smaller step helps
    run.fail(trial);
    return false;
  }
  h *= 0.25;
  ++run.retries();
  if (h >= kMinStepRel * std::max(1.0, t)) return true;
  run.fail(Status::failure(trial.t, Failure::StepUnderflow,
                           "step size underflow retrying a failed trial stage (last: " + trial.cause + ")"));
  return false;
}

// Adaptive: GSL's evolve loop; the method's correction runs after every
// accepted step, and stepper and evolve are reset so they see the corrected state.
void runAdaptive(Integration& run, const RunSpec& spec, long n_out, Eigen::VectorXd& y) {
  const int n = run.dynamics().size();
  std::unique_ptr<gsl_odeiv2_step, GslDeleter> step(gsl_odeiv2_step_alloc(*info(spec.integrator).gsl, n));
  std::unique_ptr<gsl_odeiv2_control, GslDeleter> ctl(gsl_odeiv2_control_standard_new(spec.tol, spec.tol, 1.0, 0.0));
  std::unique_ptr<gsl_odeiv2_evolve, GslDeleter> evo(gsl_odeiv2_evolve_alloc(n));
  GslParams params(run, n);
  gsl_odeiv2_system sys{gslRhs, gslJacobian, static_cast<size_t>(n), &params};
  double t = 0, h = std::min(1e-3, spec.output_dt);
  const bool corrects = run.dynamics().correctsAfterStep();
  run.retryTrialFailures(spec.options.retry_failed_steps);
  const bool limits = run.limitsActive();
  Eigen::VectorXd y0(limits ? n : 0), yerr(limits ? n : 0);
  // The stepper's own step of tau from `from` at `start` into `out` (a stop's location, the rest of a step).
  auto advance = [&](double start, double tau, const Eigen::VectorXd& from, Eigen::VectorXd& out) {
    out = from;
    gsl_odeiv2_step_reset(step.get());
    const int st = gsl_odeiv2_step_apply(step.get(), start, tau, out.data(), yerr.data(), nullptr, nullptr, &sys);
    if (const Status trial = run.takeTrialFailure(); !trial.ok) return run.fail(trial);
    if (st != GSL_SUCCESS) return run.fail(Status::failure(start, Failure::IntegratorStopped, std::string("integrator stopped: ") + gsl_strerror(st)));
    return true;
  };
  // A sampled controller's instants t_c = c period end steps as the outputs do; its torques jump there (theory.md §18).
  const ControlLoop& control = run.dynamics().control();
  long c = 0;
  double t_c = std::numeric_limits<double>::infinity();
  if (control.sampled()) run.sampleControl(0.0, y.data()), t_c = control.period();
  for (long k = 1; k <= n_out; ++k) {
    const double t_out = k * spec.output_dt;
    while (t < t_out) {
      // (An instant within round-off of the output is the output's: no step of an ulp.)
      const double t_to = t_c < t_out - kSameInstantRel * std::max(1.0, t_out) ? t_c : t_out;
      const bool cut = h > t_to - t;  // GSL ends such a step at t_to (when it is accepted at that length)
      const double t0 = t;
      if (limits) y0 = y;
      const int status = gsl_odeiv2_evolve_apply(evo.get(), ctl.get(), step.get(), &sys, &t, t_to, &h, y.data());
      const Status trial = run.takeTrialFailure();
      if (!trial.ok) {  // GSL restored t and y: retry smaller, or give up
        if (!retrySmaller(run, trial, t, h)) return;
        gsl_odeiv2_step_reset(step.get());
        gsl_odeiv2_evolve_reset(evo.get());
        continue;
      }
      if (status != GSL_SUCCESS) {
        run.fail(Status::failure(t, Failure::IntegratorStopped, std::string("integrator stopped: ") + gsl_strerror(status)));
        return;
      }
      if (limits) {  // a stop within the step: located, applied, the rest stepped; a held coordinate let go
        const bool crossed = run.limitsCrossed(y.data());
        if (!run.limitEvents(t0, t - t0, y0, y, advance)) return;
        if (crossed) {  // the state jumped: the stepper and evolve start afresh
          gsl_odeiv2_step_reset(step.get());
          gsl_odeiv2_evolve_reset(evo.get());
        }
      }
      if (!run.accept(t, y.data())) return;
      if (cut && t == t_out) ++run.gridCutSteps();
      if (std::abs(t - t_c) <= kSameInstantRel * std::max(1.0, t)) {  // a control sample: the torques jump, the stepper and evolve start afresh
        run.sampleControl(t, y.data());
        t_c = static_cast<double>(++c + 1) * control.period();
        gsl_odeiv2_step_reset(step.get());
        gsl_odeiv2_evolve_reset(evo.get());
      }
      // A corrected state is not the continuation of the step: the stepper and
      // the evolve object (which reuses the last derivative as the next step's
      // first stage) must both start afresh.
      if (corrects) {
        gsl_odeiv2_step_reset(step.get());
        gsl_odeiv2_evolve_reset(evo.get());
      }
      if (h < kMinStepRel * std::max(1.0, t)) {
        run.fail(Status::failure(t, Failure::StepUnderflow, "step size underflow (h = " + gnum(h) + ")"));
        return;
      }
    }
    run.sample(t_out, y.data());
  }
}

// A DAE run: IDA integrates the formation and the loops itself (solver/ida.hpp);
// each output sample is its interpolant at the output time (it steps past
// outputs, not stopped at each), sampled as every run's is.
// Returns the rank of G it integrated (-1 without loops).
int runIda(Integration& run, const RunSpec& spec, long n_out, Eigen::VectorXd& y, Trajectory& tr) {
  const Model& m = run.dynamics().model();
  IdaRun ida(m, spec.tol, spec.output_dt, n_out * spec.output_dt);
  for (long k = 1; k <= n_out; ++k) {
    const Status s = ida.advance(k * spec.output_dt);
    ida.state(y.data());
    if (!s) {
      run.fail(s);
      break;
    }
    run.sample(k * spec.output_dt, y.data());
    // IDA holds the rows it chose at the start; where they stop describing
    // the loops (a singular start), its state leaves them: a failure, as
    // every in-house run's after its steps (Dynamics::afterStep).
    if (const Status open = run.dynamics().loopsOpen(k * spec.output_dt); !open) {
      run.fail(open);
      break;
    }
  }
  tr.steps = ida.steps();
  run.countEvaluations(ida.residualEvaluations());
  return m.loops.empty() ? -1 : ida.rank();
}

// CVODE's BDF on the method's y' (solver/ode_bdf.hpp): each of its own steps is
// accepted (checked) as every adaptive run's is, and each output sample is
// its interpolating polynomial at the output time (IDA's samples are too).
void runMultistep(Integration& run, const RunSpec& spec, long n_out, Eigen::VectorXd& y) {
  const int n = run.dynamics().size();
  const bool retry = spec.options.retry_failed_steps;
  run.retryTrialFailures(retry);
  auto rhs = [&run, retry](double t, const double* yy, double* dy) { return run.evaluate(t, yy, dy) ? 0 : (retry ? 1 : -1); };
  BdfSolver bdf(n, rhs, y.data(), spec.tol, spec.output_dt, n_out * spec.output_dt);
  Eigen::VectorXd checked(n);  // the step's state as accept() checks it: CVODE keeps its own
  long k = 1;
  while (k <= n_out) {
    if (!bdf.step()) {
      const Status trial = run.takeTrialFailure();
      run.fail(Status::failure(bdf.t(), Failure::IntegratorStopped,
                               "CVODE stopped: " + bdf.error() + (trial.ok ? "" : " (last failed evaluation: " + trial.cause + ")")));
      break;
    }
    if (!run.takeTrialFailure().ok) ++run.retries();  // CVODE cut that step and went on
    checked = Eigen::Map<const Eigen::VectorXd>(bdf.y(), n);
    if (!run.accept(bdf.t(), checked.data())) break;
    for (; k <= n_out && k * spec.output_dt <= bdf.t(); ++k) {
      bdf.interpolate(k * spec.output_dt, y.data());
      run.sample(k * spec.output_dt, y.data());
    }
  }
  if (k <= n_out) y = Eigen::Map<const Eigen::VectorXd>(bdf.y(), n);  // where it ended
}

// The trapezoidal rule of the augmented Lagrangian (solver/augmented_lagrangian.hpp):
// exact multiples of dt, every step checked as the fixed-step rows' are.
// Returns its Newton counts and G's rank.
LoopStats runTrapezoidal(Integration& run, const RunSpec& spec, long n_out, long per_output, Eigen::VectorXd& y) {
  const Model& m = run.dynamics().model();
  AugmentedLagrangianRun al(m, spec.options.loops, spec.dt, y.data());
  for (long k = 1; k <= n_out; ++k) {
    bool ok = true;
    for (long s = 0; s < per_output && ok; ++s) {
      const double t = ((k - 1) * per_output + s) * spec.dt;
      const Status st = al.step(t, y.data());
      ok = st ? run.accept(t + spec.dt, y.data()) : run.fail(st);
    }
    if (!ok) break;
    run.sample(k * spec.output_dt, y.data());
  }
  run.countEvaluations(al.evaluations());
  return al.stats();
}

}  // namespace

namespace {

// A multistep scheme's history is of its own states: a method that corrects
// the state after a step (a Jacobi correction, eigen-block's re-clustering)
// or a formulation that projects it onto the loops would break it.
// The formulations that leave q and u as the integrator made them, from the table: "baumgarte or udwadia-kalaba".
std::string stateKeepingFormulations() {
  std::string out;
  for (const FormulationInfo& f : formulationTable())
    if (!f.corrects_state && !f.brings_integrator) out += (out.empty() ? "" : " or ") + std::string(f.name);
  return out;
}

void refuseCorrections(const Model& m, const RunSpec& spec, const IntegratorInfo& scheme) {
  const MethodInfo& method = info(spec.method);
  const std::string why = std::string("integrator ") + scheme.name + " is multistep: it cannot take a state corrected between its steps; ";
  if (method.correction != Correction::None || method.extra == ExtraState::CD)
    throw std::invalid_argument(why + "method " + method.name + " corrects its state after every step (run eigen, classical or articulated)");
  const FormulationInfo& f = formulationRow(spec.options.loops.formulation);
  if (!m.loops.empty() && f.corrects_state)
    throw std::invalid_argument(why + "formulation " + f.name + " corrects q and u after every step (run " + stateKeepingFormulations() + ")");
}

// Joint control (theory.md §18): the one-step integrators sample it at its
// instants; IDA and the trapezoidal rule form B themselves without it, and a
// multistep integrator cannot stop at each sample.
void refuseControl(const Model& m, const RunSpec& spec, const IntegratorInfo& scheme) {
  if (!m.has_control) return;
  const std::string why = std::string("integrator ") + scheme.name + ": ";
  if (scheme.dae || scheme.augmented_lagrangian)
    throw std::invalid_argument(why + "joint control is not built into its own formation (run rk4, rk8pd, rkf45, bsimp or cvode)");
  if (m.control_period > 0 && !(scheme.fixed_step || scheme.gsl))
    throw std::invalid_argument(why + "a sampled controller (joint.control.period " + gnum(m.control_period) +
                                " s) needs an integrator that stops at each sample (rk4 and the fixed-step rows, rk8pd, rkf45, bsimp)");
  if (spec.fixedStep())
    if (const std::string why = controlStepRefusal(m, spec.dt); !why.empty()) throw std::invalid_argument(why);
}

}  // namespace

void refuseUnrunnable(const Model& m, const RunSpec& spec) {
  const IntegratorInfo& scheme = info(spec.integrator);
  if (scheme.stepsItself() && !info(spec.method).formation_udot)
    throw std::invalid_argument(std::string("integrator ") + scheme.name + " integrates the formation's A and B itself, never a method's u': " +
                                "method " + methodName(spec.method) + "'s u' comes from outside the formation, so it would run as " +
                                "classical (run it under an integrator that steps its u': rk4, rk8pd, cvode, ...)");
  if (scheme.stepsItself() && info(spec.method).extra != ExtraState::None)
    throw std::invalid_argument(std::string("integrator ") + scheme.name + " integrates the formation's A and B itself: method " +
                                methodName(spec.method) + " carries its own state (run it with classical)");
  if (!scheme.stepped())  // a row no code of ours steps (a recorded run's)
    throw std::invalid_argument(std::string("integrator ") + scheme.name + ": " + scheme.summary);
  if (scheme.augmented_lagrangian)
    if (const int b = firstQuaternionBody(m); b >= 0)
      throw std::invalid_argument("integrator trapezoidal integrates q' = u: body '" + m.bodies[b].name + "' has a " +
                                  jointRow(m.bodies[b].joint.type).name + " joint (a quaternion)");
  if (scheme.multistep) refuseCorrections(m, spec, scheme);
  if (!m.limited.empty() && !(scheme.fixed_step || scheme.gsl) )
    throw std::invalid_argument(std::string("integrator ") + scheme.name + ": joint limits are events of the in-house one-step "
                                "integrators (rk4 and the fixed-step rows, rk8pd, rkf45, bsimp), which locate each stop on their own step");
  refuseControl(m, spec, scheme);
  if (m.loops.empty() || scheme.dae) return;
  // A formulation that brings its own integrator runs under no other, and that integrator runs no other formulation.
  const FormulationInfo& f = formulationRow(spec.options.loops.formulation);
  if (f.brings_integrator && f.own_integrator != spec.integrator)
    throw std::invalid_argument(std::string("formulation ") + f.name + " runs under its own integrator " + info(f.own_integrator).name +
                                ", not " + scheme.name);
  if (const FormulationInfo* brings = formulationBringing(spec.integrator); brings && brings != &f)
    throw std::invalid_argument(std::string("integrator ") + scheme.name + " on a mechanism runs the formulation " + brings->name +
                                ", not " + f.name);
}

Trajectory simulate(const Model& m, const CheckedRunSpec& checked_spec, const SampleObserver& observe) {
  const RunSpec& spec = checked_spec;
  const IntegratorInfo& scheme = info(spec.integrator);
  refuseUnrunnable(m, spec);
  const long n_out = outputIntervals(spec.t_end, spec.output_dt);
  const long per_output = spec.fixedStep() ? stepsPerOutput(spec.output_dt, spec.dt) : 1;
  Dynamics dyn(m, spec.method, spec.options);  // throws for another engine's method
  Trajectory tr = makeTrajectory(m, spec);
  Eigen::VectorXd y = dyn.initialState(m.q0(), m.u0());
  Integration run(dyn, spec, tr, observe);
  run.sample(0.0, y.data());
  tr.sample_time_s = 0;
  gsl_error_handler_t* old = gsl_set_error_handler_off();  // GSL errors become statuses, never aborts
  const double c0 = cpuSeconds();
  int dae_rank = -1;
  LoopStats al_stats;
  if (scheme.dae)
    dae_rank = runIda(run, spec, n_out, y, tr);
  else if (scheme.augmented_lagrangian)
    al_stats = runTrapezoidal(run, spec, n_out, per_output, y);
  else if (scheme.multistep)
    runMultistep(run, spec, n_out, y);
  else if (spec.fixedStep())
    runFixed(run, spec, n_out, per_output, y);
  else
    runAdaptive(run, spec, n_out, y);
  tr.run_time_s = cpuSeconds() - c0 - tr.sample_time_s;
  gsl_set_error_handler(old);
  run.finish(y.data());
  if (scheme.dae && tr.has_loops) tr.loops.rank_min = tr.loops.rank_max = dae_rank;
  if (scheme.augmented_lagrangian) {  // its Newton and the rank of G; the violations are the samples' and steps', as every run's
    tr.loops.newton_solves = al_stats.newton_solves;
    tr.loops.newton_iterations = al_stats.newton_iterations;
    tr.loops.newton_unconverged = al_stats.newton_unconverged;
    tr.loops.newton_at_roundoff = al_stats.newton_at_roundoff;
    tr.loops.rank_min = al_stats.rank_min;
    tr.loops.rank_max = al_stats.rank_max;
  }
  return tr;
}

}  // namespace em
