#include "reference/mujoco_engine.hpp"

#include <cmath>
#include <ctime>
#include <stdexcept>

#include <mujoco/mujoco.h>

#include "reference/engine.hpp"
#include "reference/mujoco_peer.hpp"

namespace em {

namespace {

// MuJoCo's schemes, as its row lists them.
int scheme(Integrator i) {
  const std::string name = integratorName(i);
  if (name == "euler") return mjINT_EULER;
  if (name == "rk4") return mjINT_RK4;
  if (name == "implicit") return mjINT_IMPLICIT;
  throw std::logic_error("no MuJoCo integrator for " + name);
}

bool finite(const Eigen::VectorXd& x) { return x.allFinite(); }

}  // namespace

Trajectory simulateMujoco(const Model& m, const RunSpec& spec, const SampleObserver& observe) {
  checkRunSpec(spec);
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
  const long evals_per_step = spec.integrator == Integrator::RK4 ? 4 : 1;  // rk4: the in-house tableau
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

namespace {

// MuJoCo's equations at any state (mj_forward), for crosscheck and `equations`.
class MujocoModel : public EngineModel {
 public:
  explicit MujocoModel(std::unique_ptr<MujocoPeer> peer) : peer_(std::move(peer)) {
    peer_->configure(mjINT_RK4, 1e-3);  // energies on: kinetic and potential at every forward
  }
  EngineEquations at(const Eigen::VectorXd& q, const Eigen::VectorXd& u) override {
    peer_->setState(q, u);
    peer_->forward();
    return {peer_->massMatrix(), peer_->rhs(), peer_->acceleration(), peer_->kineticEnergy(), peer_->potentialEnergy()};
  }
  std::vector<CompiledMass> compiledMass() override { return peer_->compiledMass(); }

 private:
  std::unique_ptr<MujocoPeer> peer_;
};

}  // namespace

EngineRow mujocoEngine() {
  return {"mujoco",
          "MuJoCo 2.2's own dynamics (CRB mass matrix, sparse LTDL): a second independent engine, fixed step",
          {{"rk4", true, "MuJoCo's RK4, the in-house tableau", "o"},
           {"euler", true, "MuJoCo's semi-implicit Euler (velocity first, position from the new velocity; damping implicit), fixed step", "P"},
           {"implicit", true, "MuJoCo's implicit-in-velocity Euler (damping and velocity-dependent forces implicit), fixed step", "X"}},
          "rk4",
          "rk4",  // MuJoCo 2.2 has no adaptive scheme
          HUGE_VAL,
          "tab:red",
          simulateMujoco,
          [](const Model& m) -> std::unique_ptr<EngineModel> {
            return std::make_unique<MujocoModel>(std::make_unique<MujocoPeer>(m));
          },
          [](const Model& m, const UrdfSource& u) -> std::unique_ptr<EngineModel> {
            return std::make_unique<MujocoModel>(std::make_unique<MujocoPeer>(m, u.text, u.joints, u.locked,
                                                                               u.balance_inertia, u.floating_joint));
          },
          [] { return std::string(mj_versionString()); },
          "MuJoCo against the in-house formation given MuJoCo's compiled masses, CMs and inertias;\n"
          " MuJoCo rounds a full inertia tensor when it diagonalizes it; judged: all but MuJoCo's raw u', docs/urdf.md"};
}

}  // namespace em
