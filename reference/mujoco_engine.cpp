#include "reference/mujoco_engine.hpp"

#include <cmath>
#include <ctime>
#include <stdexcept>

#include <mujoco/mujoco.h>

#include "reference/mujoco_peer.hpp"

namespace em {

namespace {

int scheme(Integrator i) {
  switch (i) {
    case Integrator::Euler: return mjINT_EULER;
    case Integrator::RK4: return mjINT_RK4;
    case Integrator::Implicit: return mjINT_IMPLICIT;
    default: throw std::logic_error(std::string("no MuJoCo integrator for ") + integratorName(i));
  }
}

bool finite(const Eigen::VectorXd& x) { return x.allFinite(); }

}  // namespace

Trajectory simulateMujoco(const Model& m, const RunSpec& spec, const SampleObserver& observe) {
  checkRunSpec(spec);
  if (spec.engine() != Engine::Mujoco) throw std::invalid_argument(std::string(methodName(spec.method)) + " is not MuJoCo");
  const long n_out = outputIntervals(spec.t_end, spec.output_dt), per_output = stepsPerOutput(spec.output_dt, spec.dt);
  MujocoPeer peer(m);
  peer.configure(scheme(spec.integrator), spec.dt);
  peer.setState(m.q0(), m.u0());
  Trajectory tr = makeTrajectory(m, spec);
  Eigen::VectorXd q, u;
  double W = 0, cpu = 0;  // W_diss: sum of c u^2 dt at each step's start (first order in dt)
  auto sample = [&](double t) {
    peer.forward();  // positions, energies of the current state (a step leaves them a stage behind)
    peer.getState(q, u);
    const double T = peer.kineticEnergy();
    appendSample(tr, m, t, q.data(), u.data(), peer.poses(), {T + peer.potentialEnergy(), T, W});
  };
  sample(0.0);
  const long evals_per_step = spec.integrator == Integrator::RK4 ? 4 : 1;
  for (long k = 1; k <= n_out && !tr.failed(); ++k) {
    const std::clock_t c0 = std::clock();
    for (long s = 0; s < per_output; ++s) {
      if (m.has_dampers) W += spec.dt * peer.dissipationRate();
      peer.step();
      ++tr.steps;
      const std::string warned = peer.warnings();
      if (!warned.empty()) {  // MuJoCo has reset its state (and time): the step count says when
        markFailed(tr, static_cast<double>(tr.steps) * spec.dt, Failure::Engine, "MuJoCo: " + warned);
        break;
      }
    }
    cpu += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    if (tr.failed()) break;
    sample(k * spec.output_dt);
    if (!finite(tr.q.back()) || !finite(tr.u.back())) markFailed(tr, k * spec.output_dt, Failure::NonFinite, "non-finite state (NaN or Inf)");
    else if (double umax = tr.u.back().cwiseAbs().maxCoeff(); umax > spec.options.blowup_speed)
      markFailed(tr, k * spec.output_dt, Failure::BlowUp, "blow-up: max |u| exceeds the bound");
    if (observe) observe(k * spec.output_dt);
  }
  tr.run_time_s = cpu;
  tr.rhs_evals = tr.steps * evals_per_step;
  return tr;
}

}  // namespace em
