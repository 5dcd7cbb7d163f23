#include "reference/mujoco.hpp"

#include <cmath>
#include <ctime>
#include <stdexcept>

#include <mujoco/mujoco.h>

#include "reference/engine.hpp"
#include "reference/fixed_step.hpp"
#include "reference/mujoco_system.hpp"
#include "solver/method.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

// MuJoCo's schemes: their ids, the order of its row's schemes (mujocoEngine), and MuJoCo's integrator of each.
enum MujocoScheme { kMujocoRk4, kMujocoEuler, kMujocoImplicit, kMujocoSchemes };
constexpr int kMujocoIntegrator[kMujocoSchemes] = {mjINT_RK4, mjINT_EULER, mjINT_IMPLICIT};

int scheme(const RunSpec& spec) { return kMujocoIntegrator[schemeIndex(spec.engine(), spec.integrator)]; }

// Evaluations of MuJoCo's equations: mj_passive runs once in every forward
// pass, a stage of its integrators included (rk4: four per step).
thread_local long g_evaluations = 0;
void countEvaluation(const mjModel*, mjData*) { ++g_evaluations; }

// MuJoCo raises a closure's solref time constant below two steps to two
// steps (its refsafe rule): such a run would not be the one asked for, and
// the report would record the value asked (issue 73, item 5).
std::string settingsRefusal(const Model& m, const RunSpec& spec) {
  if (!m.limited.empty()) {  // the same rule for its limits' solref
    const double tl = info(spec.method).param("mujoco_limit_solref_time", spec.options);
    if (tl < 2 * spec.dt)
      return "--mujoco-limit-solref-time " + gnum(tl) + ": below two steps (2 dt = " + gnum(2 * spec.dt) +
             " s), which MuJoCo raises to 2 dt: give at least " + gnum(2 * spec.dt) + " or a smaller --dt";
  }
  if (m.loops.empty()) return "";
  const double tc = info(spec.method).param("mujoco_solref_time", spec.options);
  if (tc >= 2 * spec.dt) return "";
  return "--mujoco-solref-time " + gnum(tc) + ": below two steps (2 dt = " + gnum(2 * spec.dt) +
         " s), which MuJoCo raises to 2 dt: give at least " + gnum(2 * spec.dt) + " or a smaller --dt";
}

// MuJoCo stepped by the one fixed-step loop (reference/fixed_step.hpp).
class MujocoStepper : public FixedStepEngine {
 public:
  MujocoStepper(const Model& m, const RunSpec& spec) : peer_(m) {
    peer_.configure(scheme(spec), spec.dt, false);  // energies only at the samples, outside the timer
    if (!m.loops.empty()) {
      const MethodInfo& row = info(spec.method);
      const double solref[2] = {row.param("mujoco_solref_time", spec.options), row.param("mujoco_solref_damping", spec.options)};
      const double solimp[3] = {row.param("mujoco_solimp_d0", spec.options), row.param("mujoco_solimp_dwidth", spec.options),
                                row.param("mujoco_solimp_width", spec.options)};
      peer_.soften(solref, solimp);
    }
    if (!m.limited.empty()) {
      const MethodInfo& row = info(spec.method);
      const double solref[2] = {row.param("mujoco_limit_solref_time", spec.options), row.param("mujoco_limit_solref_damping", spec.options)};
      peer_.softenLimits(solref);
    }
    peer_.setState(m.q0(), m.u0());
    peer_.forward();
    mjcb_passive = countEvaluation;
  }
  ~MujocoStepper() override { mjcb_passive = nullptr; }
  std::string step() override {
    const long before = g_evaluations;
    peer_.step();
    evaluations_ += g_evaluations - before;
    const std::string warned = peer_.warnings();  // MuJoCo has then reset its state (and time)
    return warned.empty() ? "" : "MuJoCo: " + warned;
  }
  long evaluations() const override { return evaluations_; }
  void applyControl(const Eigen::VectorXd& tau) override { peer_.applyControl(tau); }
  void state(Eigen::VectorXd& q, Eigen::VectorXd& u) override { peer_.getState(q, u); }
  void sample(std::vector<Pose>& poses, double& kinetic, double& potential) override {
    peer_.computeEnergies(true);
    peer_.forward();  // positions, energies of the current state (a step leaves them a stage behind)
    peer_.computeEnergies(false);
    poses = peer_.poses();
    kinetic = peer_.kineticEnergy();
    potential = peer_.potentialEnergy();
  }
  void dissipation(double& P, double& Pdot) override {
    peer_.forward();  // qacc at the current state (the next step's forward recomputes the same)
    P = peer_.dissipationRate();
    Pdot = peer_.dissipationRateDerivative();
  }

 private:
  MujocoSystem peer_;
  long evaluations_ = 0;
};

}  // namespace

Trajectory simulateMujoco(const Model& m, const CheckedRunSpec& spec, const SampleObserver& observe) {
  return simulateFixedStep<MujocoStepper>(m, spec, observe);
}

namespace {

// MuJoCo's equations at any state (mj_forward), for crosscheck and `equations`.
class MujocoModel : public EngineModel {
 public:
  explicit MujocoModel(std::unique_ptr<MujocoSystem> peer) : peer_(std::move(peer)) {
    peer_->configure(mjINT_RK4, 1e-3);  // energies on: kinetic and potential at every forward
  }
  EngineEquations at(const Eigen::VectorXd& q, const Eigen::VectorXd& u) override {
    peer_->setState(q, u);
    peer_->forward();
    return {peer_->massMatrix(), peer_->rhs(), peer_->acceleration(), peer_->kineticEnergy(), peer_->potentialEnergy()};
  }
  void forward(const Eigen::VectorXd& q, const Eigen::VectorXd& u) override {
    peer_->setState(q, u);
    peer_->forward();
  }
  std::vector<CompiledMass> compiledMass() override { return peer_->compiledMass(); }

 private:
  std::unique_ptr<MujocoSystem> peer_;
};

}  // namespace

namespace {

// MuJoCo's compiler diagonalizes a full inertia tensor (its principal axes to
// 1e-12 absolute), so on a scene with products of inertia its u' is off the
// exact one by ~3e-7 relative (measured on the Z1 arm, docs/urdf.md).
std::string fullInertiaNote(const Model& m) {
  for (const Body& b : m.bodies)
    if (b.J(0, 1) != 0 || b.J(0, 2) != 0 || b.J(1, 2) != 0)
      return "body '" + b.name + "' has products of inertia: MuJoCo's compiler diagonalizes full inertia tensors "
             "(principal axes to 1e-12 absolute), which leaves its u' ~3e-7 relative off the exact one on such scenes; "
             "an agreement below that is not to be expected of MuJoCo here";
  return "";
}

// What of a mechanism MuJoCo's row does not map (reference/mujoco_system.cpp maps
// ball, hinge and weld closures as connects, point spring-dampers as spatial
// tendons with stiffness and damping, drives as qfrc_applied).
std::string mechanismRefusal(const Model& m) {
  if (std::string why = unmappedLoop(m, kMjLoops, "MuJoCo 2.2's equality constraints (connect, weld)"); !why.empty()) return why;
  for (const Body& b : m.bodies)
    if (b.joint.torque.size() > 0 && (b.joint.type == JointType::Ball || b.joint.type == JointType::Free))
      return "the drive on body '" + b.name + "': MuJoCo reads a " + jointTypeName(b.joint.type) +
             " joint's angular speed in the child's frame, where a constant torque of ours is not constant";
  return "";
}

}  // namespace

namespace {

// mujoco-udot: MuJoCo's u' (mj_forward) under the in-house integrators:
// MuJoCo's dynamics, its compiled inertias included, apart from its integrator.
class MujocoUdot final : public MethodImpl {
 public:
  explicit MujocoUdot(const Model& m) : peer_(m), q_(m.nq), u_(m.nu) {
    peer_.configure(mjINT_RK4, 1e-3, false);  // the drives set; no energies: u' alone is asked
  }
  bool needsEquations() const override { return false; }
  bool needsKinematics() const override { return false; }
  Status rates(double, const double* q, const double* u, const Workspace&, const double*, double* udot, double*,
               EvalInfo&) override {
    q_ = Eigen::Map<const Eigen::VectorXd>(q, q_.size());
    u_ = Eigen::Map<const Eigen::VectorXd>(u, u_.size());
    peer_.setState(q_, u_);
    peer_.forward();
    peer_.acceleration(udot);
    return {};
  }

 private:
  MujocoSystem peer_;
  Eigen::VectorXd q_, u_;  // (nq), (nu): the state handed to setState
};

std::unique_ptr<MethodImpl> makeMujocoUdot(const Model& m, const MethodInfo&, const MethodOptions&) {
  return std::make_unique<MujocoUdot>(m);
}

}  // namespace

EngineRow mujocoEngine() {
  EngineRow r;
  r.info.name = "mujoco";
  r.info.summary = "MuJoCo 2.2's own dynamics (CRB mass matrix, sparse LTDL): a second independent engine, fixed step";
  r.info.schemes.resize(kMujocoSchemes);  // each at its id
  r.info.schemes[kMujocoRk4] = {"rk4", true, "MuJoCo's RK4, the in-house tableau", "o"};
  r.info.schemes[kMujocoEuler] = {"euler", true, "MuJoCo's semi-implicit Euler (velocity first, position from the new velocity; damping implicit), fixed step", "P"};
  r.info.schemes[kMujocoImplicit] = {"implicit", true, "MuJoCo's implicit-in-velocity Euler (damping and velocity-dependent forces implicit), fixed step", "X"};
  r.info.fixed_scheme = "rk4";
  r.info.adaptive_scheme = "rk4";  // MuJoCo 2.2 has no adaptive scheme
  r.info.colour = "tab:red";
  // Its closures' softness, MuJoCo's defaults (mjModel's eq_solref, eq_solimp), read only where loops are.
  r.info.params = {
      {"mujoco_solref_time", 0.02, 0, 1e3, false, "MuJoCo: its closures' solref time constant (s): how fast a loop's violation is pulled back (its default 0.02)", nullptr, true},
      {"mujoco_solref_damping", 1, 0, 1e3, false, "MuJoCo: its closures' solref damping ratio (its default 1, critical)", nullptr, true},
      {"mujoco_solimp_d0", 0.9, 0, 0.9999, false, "MuJoCo: its closures' solimp impedance at zero violation (its default 0.9)", nullptr, true},
      {"mujoco_solimp_dwidth", 0.95, 0, 0.9999, false, "MuJoCo: its closures' solimp impedance at a violation of width (its default 0.95)", nullptr, true},
      {"mujoco_solimp_width", 0.001, 0, 1e3, false, "MuJoCo: its closures' solimp width (m or rad; its default 0.001)", nullptr, true},
      {"mujoco_limit_solref_time", 0.02, 0, 1e3, false, "MuJoCo: its joint limits' solreflimit time constant (s; its default 0.02)", nullptr, false, true},
      {"mujoco_limit_solref_damping", 1, 0, 1e3, false, "MuJoCo: its joint limits' solreflimit damping ratio (its default 1, critical: no rebound; below 1 a stop bounces)", nullptr, false, true}};
  // Beside the reference: rk4 at 1e-4 s, fine enough that its own error (~dt^4) is below the reference's tolerance.
  r.info.roles.second_scheme = "rk4";
  r.info.roles.second_dt = 1e-4;
  r.code.simulate = simulateMujoco;
  r.code.model = [](const Model& m) -> std::unique_ptr<EngineModel> {
    return std::make_unique<MujocoModel>(std::make_unique<MujocoSystem>(m));
  };
  r.code.urdf = [](const Model& m, const UrdfSource& u) -> std::unique_ptr<EngineModel> {
    return std::make_unique<MujocoModel>(std::make_unique<MujocoSystem>(m, u.text, u.joints, u.locked, u.balance_inertia, u.floating_joint));
  };
  r.code.forward_call = "MuJoCo mj_forward";
  r.code.version = [] { return std::string(mj_versionString()); };
  r.code.mass_note =
      "MuJoCo against the in-house formation given MuJoCo's compiled masses, CMs and inertias;\n"
      " MuJoCo rounds a full inertia tensor when it diagonalizes it; judged: all but MuJoCo's raw u', docs/urdf.md";
  r.code.scene_note = [](const Model& m) {
    const std::string inertia = fullInertiaNote(m);
    if (m.limited.empty()) return inertia;
    return (inertia.empty() ? "" : inertia + "; ") +
           "joint limits: MuJoCo's soft limits (limited, range) at solreflimit mujoco_limit_solref_time, mujoco_limit_solref_damping "
           "(its defaults 0.02 1: a critically damped stop, no rebound) and its default solimplimit 0.9 0.95 0.001: e is not mapped";
  };
  r.code.limits_refusal = [](const Model& m) -> std::string {  // one MuJoCo hinge or slide per coordinate
    for (const Body& b : m.bodies)
      if (b.joint.limits && b.joint.type != JointType::Revolute && b.joint.type != JointType::Prismatic && b.joint.type != JointType::Universal)
        return std::string("the limits of body '") + b.name + "': MuJoCo's limits are mapped on revolute, prismatic and universal joints, not on a " +
               jointTypeName(b.joint.type) + " joint";
    return "";
  };
  r.code.udot_method = {"mujoco-udot", "MuJoCo's u' (mj_forward: its compiled masses, CRB mass matrix and bias forces) under "
                                       "the in-house integrators: MuJoCo's dynamics apart from its integrator", "#8c1c13",
                        makeMujocoUdot};
  r.code.mechanism_refusal = mechanismRefusal;
  r.code.settings_refusal = settingsRefusal;
  r.code.soft_closures =
      "MuJoCo closes loops by soft equality constraints (connects; its default solref 0.02 1, solimp 0.9 0.95 0.001): "
      "its u' of a mechanism is the regularized one, not the exact constrained u', and is printed, not judged";
  return r;
}

}  // namespace em
