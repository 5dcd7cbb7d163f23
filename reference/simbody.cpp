#include "reference/simbody.hpp"

#include "reference/engine.hpp"
#include "reference/engine_messages.hpp"
#include "solver/control.hpp"
#include "solver/mechanism/loops.hpp"
#include "solver/text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <ctime>
#include <stdexcept>

#include <Simbody.h>

// GCC 12 reports -Warray-bounds inside SimTK::Vec<3,double,4> (the stride-4
// view of a Rotation's diagonal) when Rotation's constructors are inlined
// here: a false positive in Simbody's header that SYSTEM includes do not
// silence, because it is diagnosed at the inlining site.
#pragma GCC diagnostic ignored "-Warray-bounds"

namespace em {

// Using-declarations only: `using namespace SimTK` breaks Eigen 3.4's operators.
using SimTK::MobilizedBody;
using SimTK::Rotation;
using SimTK::State;
using SimTK::Transform;
using SimTK::Vector;

namespace {

// SimTK exceptions span several indented lines; a failure cause is one line.
std::string oneLine(const std::string& s) {
  std::string out;
  for (char c : s) {
    const bool space = c == '\n' || c == ' ' || c == '\t';
    if (space && (out.empty() || out.back() == ' ')) continue;
    out += space ? ' ' : c;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

SimTK::Vec3 toSimTK(const em::Vec3& v) { return SimTK::Vec3(v.x(), v.y(), v.z()); }

em::Mat3 toEigen(const Rotation& R) {
  em::Mat3 M;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M(i, j) = R.asMat33()(i, j);
  return M;
}

SimTK::Inertia toInertia(const em::Mat3& J) {
  SimTK::Mat33 M;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M(i, j) = J(i, j);
  return SimTK::Inertia(M);
}

// A joint kind as a Simbody mobilizer, the one mapping of kinds: the
// orientation of its frames F (in the parent) and M (in the body), the same
// for both so that at zero coordinates the body frame is parallel to the
// parent's; the mobilizer; and where Simbody keeps our coordinate k and speed
// k: at (k + shift) mod their number.
struct Mobilizer {
  Rotation frame;
  MobilizedBody (*make)(MobilizedBody& parent, const Transform& X_PF, const SimTK::Body& body, const Transform& X_BM);
  int q_shift = 0, u_shift = 0;
};

template <class M>
MobilizedBody made(MobilizedBody& parent, const Transform& X_PF, const SimTK::Body& body, const Transform& X_BM) {
  return M(parent, X_PF, body, X_BM);
}

Mobilizer mobilizer(const Joint& j) {
  using SimTK::UnitVec3;
  switch (j.type) {
    case JointType::Revolute:  // Pin turns about its frames' common z: put z on the axis.
      return {Rotation(UnitVec3(toSimTK(j.axis[0])), SimTK::ZAxis), made<MobilizedBody::Pin>};
    case JointType::Universal:  // Universal: about x, then the new y.
      return {Rotation(UnitVec3(toSimTK(j.axis[0])), SimTK::XAxis, toSimTK(j.axis[1]), SimTK::YAxis),
              made<MobilizedBody::Universal>};
    case JointType::Prismatic:  // Slider slides along its frames' common x: put x on the axis.
      return {Rotation(UnitVec3(toSimTK(j.axis[0])), SimTK::XAxis), made<MobilizedBody::Slider>};
    case JointType::Gimbal:  // Gimbal (x-y-z body-fixed) and Ball act in the parent's axes, as ours.
      return {Rotation(), made<MobilizedBody::Gimbal>};
    case JointType::Ball:  // [w,x,y,z] as ours, w_FM in F = parent axes
      return {Rotation(), made<MobilizedBody::Ball>};
    case JointType::Free:  // q = [quaternion, p_FM], u = [w_FM, v_FM] (in F); ours [x, quaternion], [v, w]
      return {Rotation(), made<MobilizedBody::Free>, 4, 3};
    case JointType::Planar:  // q = [angle about F's z, x, y along F's x, y]: F = (e1, e2, e1 x e2); ours [s1, s2, angle]
      return {Rotation(UnitVec3(toSimTK(j.axis[0])), SimTK::XAxis, toSimTK(j.axis[1]), SimTK::YAxis),
              made<MobilizedBody::Planar>, 1, 1};
  }
  throw std::logic_error("Simbody: a joint kind without a mobilizer");
}

// Where Simbody keeps our k-th of n (a coordinate or a speed) of a joint whose mapping shifts them.
int shifted(int k, int shift, int n) { return (k + shift) % n; }

// One damped mobility (c > 0: power c u^2 taken out) or one drive (its
// constant tau: power tau u put in, counted as -tau u): its body, which of its
// speeds, and the coefficient.
struct Damper {
  MobilizedBody mb;
  int which;
  double c;     // damping, or 0 for a drive
  double tau;   // a drive's force, or 0 for a damper
};

// A point damper between two stations: power c l'^2.
struct PointDamper {
  MobilizedBody a, b;
  SimTK::Vec3 pa, pb;
  double c;
};

// A joint controller (docs/theory.md §18) as Simbody's custom force: its
// torques on the controlled mobilities, computed from the state (continuous)
// or held since the last sample (sampled: the run stops Simbody there).
class JointControlForce : public SimTK::Force::Custom::Implementation {
 public:
  JointControlForce(const Model& m, const std::vector<int>& q_index, const std::vector<int>& u_index)
      : m_(m), q_index_(q_index), u_index_(u_index), loop_(m), q_(m.nq), u_(m.nu), tau_(m.nu) {}
  void calcForce(const State& s, SimTK::Vector_<SimTK::SpatialVec>&, SimTK::Vector_<SimTK::Vec3>&, SimTK::Vector& mobility) const override {
    torquesAt(s);
    for (int i = 0; i < m_.nu; ++i) mobility[u_index_[i]] += tau_[i];
  }
  SimTK::Real calcPotentialEnergy(const State&) const override { return 0; }
  /// Its power tau . u at s (W_diss counts it negative).
  double power(const State& s) const {
    torquesAt(s);
    return tau_.dot(u_);
  }
  /// A sample of a sampled loop at s (then held).
  void sample(const State& s) {
    read(s);
    loop_.sample(s.getTime(), q_.data(), u_.data());
  }
  const ControlLoop& loop() const { return loop_; }

 private:
  void read(const State& s) const {
    for (int i = 0; i < m_.nq; ++i) q_[i] = s.getQ()[q_index_[i]];
    for (int i = 0; i < m_.nu; ++i) u_[i] = s.getU()[u_index_[i]];
  }
  void torquesAt(const State& s) const {
    read(s);
    loop_.torques(s.getTime(), q_.data(), u_.data(), tau_);
  }
  const Model& m_;
  const std::vector<int>& q_index_;
  const std::vector<int>& u_index_;  // filled after realizeTopology, before any evaluation
  ControlLoop loop_;
  mutable Eigen::VectorXd q_, u_, tau_;  // (nq), (nu), (nu): scratch, sized once
};

// W_diss' = sum c u^2 + sum c l'^2 - sum tau u (docs/theory.md eq. (M6)), a
// Simbody measure of Velocity stage that Measure::Integrate turns into a z variable.
class DissipationRate : public SimTK::Measure::Implementation {
 public:
  DissipationRate(std::vector<Damper> dampers, std::vector<PointDamper> points, const JointControlForce* control)
      : SimTK::Measure::Implementation(1), dampers_(std::move(dampers)), points_(std::move(points)), control_(control) {}
  Implementation* cloneVirtual() const override { return new DissipationRate(*this); }
  int getNumTimeDerivativesVirtual() const override { return 0; }
  SimTK::Stage getDependsOnStageVirtual(int) const override { return SimTK::Stage::Velocity; }
  void calcCachedValueVirtual(const State& s, int, double& value) const override {
    value = 0;
    for (const Damper& d : dampers_) {
      const double u = d.mb.getOneU(s, d.which);
      value += d.c * u * u - d.tau * u;
    }
    for (const PointDamper& p : points_) {
      const SimTK::Vec3 d = p.b.findStationLocationInGround(s, p.pb) - p.a.findStationLocationInGround(s, p.pa);
      const SimTK::Vec3 v = p.b.findStationVelocityInGround(s, p.pb) - p.a.findStationVelocityInGround(s, p.pa);
      value += p.c * SimTK::square(SimTK::dot(d, v) / d.norm());
    }
    if (control_) value -= control_->power(s);  // theory.md eq. (C3)
  }

 private:
  std::vector<Damper> dampers_;
  std::vector<PointDamper> points_;
  const JointControlForce* control_;  // owned by the force subsystem, or null
};

// Its handle (SetHandle, the tag that adopts an implementation, is protected).
struct DissipationMeasure : SimTK::Measure {
  DissipationMeasure(SimTK::Subsystem& sub, std::vector<Damper> dampers, std::vector<PointDamper> points, const JointControlForce* control)
      : SimTK::Measure(sub, new DissipationRate(std::move(dampers), std::move(points), control), SetHandle()) {}
};

}  // namespace

struct SimbodySystem::Impl {
  explicit Impl(const Model& m) : model(m), matter(system), forces(system), meter(m) {
    for (const Body& b : m.bodies) {
      MobilizedBody& parent = b.parent < 0 ? matter.updGround() : mobods[b.parent];
      const SimTK::Body::Rigid body(SimTK::MassProperties(b.mass, SimTK::Vec3(0), toInertia(b.J)));
      const Mobilizer mob = mobilizer(b.joint);
      const Transform X_PF(mob.frame, toSimTK(b.joint.in_parent)), X_BM(mob.frame, toSimTK(b.joint.in_body));
      mobods.push_back(mob.make(parent, X_PF, body, X_BM));
      addSpring(b, mob.u_shift, mobods.back());
      addDrive(b, mob.u_shift, mobods.back());
    }
    // A mechanism's closures and point spring-dampers (docs/reference-engines.md, "Mechanisms").
    for (const Loop& l : m.loops) addLoop(l);
    for (const PointSpring& s : m.point_springs) addPointSpring(s);
    // Only what the scene declares (docs/theory.md §5).
    if (m.has_gravity) SimTK::Force::UniformGravity(forces, matter, toSimTK(m.gravity));
    if (m.has_control) {  // Simbody owns the implementation; `control` is its address, for samples and power
      control = new JointControlForce(m, q_index, u_index);
      SimTK::Force::Custom(forces, control);
    }
    if (tracksWork()) {
      const DissipationMeasure rate(forces, dampers, point_dampers, control);
      dissipated = SimTK::Measure::Integrate(forces, rate, SimTK::Measure::Zero(forces));
    }
    system.realizeTopology();
    state = system.getDefaultState();
    // Simbody's q and u index of each in-house coordinate and speed, fixed from here on.
    for (const Body& b : m.bodies) {
      const MobilizedBody& mb = mobods[&b - m.bodies.data()];
      const Mobilizer mob = mobilizer(b.joint);
      for (int k = 0; k < b.nq(); ++k) q_index.push_back(mb.getFirstQIndex(state) + shifted(k, mob.q_shift, b.nq()));
      for (int k = 0; k < b.nu(); ++k) u_index.push_back(mb.getFirstUIndex(state) + shifted(k, mob.u_shift, b.nu()));
    }
    setState(m.q0(), m.u0());
  }

  // Our coordinate k's spring on Simbody's mobility (k + shift) mod nu (a spring's kind has q = u).
  void addSpring(const Body& b, int shift, MobilizedBody& mb) {
    if (!b.joint.has_spring) return;
    const Spring& s = b.joint.spring;
    for (int k = 0; k < b.nu(); ++k) {
      const int at = shifted(k, shift, b.nu());
      if (s.k[k] != 0) SimTK::Force::MobilityLinearSpring(forces, mb, at, s.k[k], s.q_rest[k]);
      if (s.c[k] == 0) continue;
      SimTK::Force::MobilityLinearDamper(forces, mb, at, s.c[k]);
      dampers.push_back({mb, at, s.c[k], 0.0});
    }
  }

  // A drive: our coordinate k's constant force on Simbody's mobility (k + shift) mod nu.
  void addDrive(const Body& b, int shift, MobilizedBody& mb) {
    for (int k = 0; k < b.joint.torque.size(); ++k) {
      const int at = shifted(k, shift, b.nu());
      SimTK::Force::MobilityConstantForce(forces, mb, at, b.joint.torque[k]);
      dampers.push_back({mb, at, 0.0, b.joint.torque[k]});
    }
  }

  MobilizedBody& bodyOf(int i) { return i < 0 ? matter.updGround() : mobods[i]; }

  // A loop's held turn R_a^T R_b (Loop::rel) as Simbody's Rotation.
  static Rotation relOf(const Loop& l) {
    SimTK::Mat33 R;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) R(i, j) = l.rel(i, j);
    return Rotation(R);
  }

  // Bodies' frames sit at their CMs here, so a loop's points are Simbody stations as written.
  void addLoop(const Loop& l) {
    MobilizedBody &a = bodyOf(l.a.body), &b = bodyOf(l.b.body);
    const SimTK::Vec3 pa = toSimTK(l.a.point), pb = toSimTK(l.b.point);
    switch (l.type) {
      case LoopType::Ball:
        SimTK::Constraint::Ball(a, pa, b, pb);
        return;
      case LoopType::Hinge: {
        // The points meet, and axis_a stays square to two perpendiculars of axis_b.
        SimTK::Constraint::Ball(a, pa, b, pb);
        const SimTK::UnitVec3 axis_b(toSimTK(l.axis_b)), axis_a(toSimTK(l.axis_a));
        const SimTK::UnitVec3 p1 = axis_b.perp(), p2(SimTK::cross(axis_b, p1));
        SimTK::Constraint::ConstantAngle(b, p1, a, axis_a);
        SimTK::Constraint::ConstantAngle(b, p2, a, axis_a);
        return;
      }
      case LoopType::Weld:
        // b's frame at R_a rel: Simbody's weld makes frame F (on a) and M (on b) coincide.
        SimTK::Constraint::Weld(a, Transform(relOf(l), pa), b, Transform(pb));
        return;
      case LoopType::Universal:
        // The points meet, and axis_b stays square to axis_a (ConstantAngle's default angle: pi/2).
        SimTK::Constraint::Ball(a, pa, b, pb);
        SimTK::Constraint::ConstantAngle(a, SimTK::UnitVec3(toSimTK(l.axis_a)), b, SimTK::UnitVec3(toSimTK(l.axis_b)));
        return;
      case LoopType::Slider:
        // b's point on a's line through pa along axis_a, and b's frame at R_a rel.
        SimTK::Constraint::PointOnLine(a, SimTK::UnitVec3(toSimTK(l.axis_a)), pa, b, pb);
        SimTK::Constraint::ConstantOrientation(a, relOf(l), b, Rotation());
        return;
    }
  }

  void addPointSpring(const PointSpring& s) {
    MobilizedBody &a = bodyOf(s.a.body), &b = bodyOf(s.b.body);
    const SimTK::Vec3 pa = toSimTK(s.a.point), pb = toSimTK(s.b.point);
    if (s.k != 0) SimTK::Force::TwoPointLinearSpring(forces, a, pa, b, pb, s.k, s.length);
    if (s.c == 0) return;
    SimTK::Force::TwoPointLinearDamper(forces, a, pa, b, pb, s.c);
    point_dampers.push_back({a, b, pa, pb, s.c});
  }

  void setState(const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
    Vector& Q = state.updQ();
    Vector& U = state.updU();
    for (int i = 0; i < model.nq; ++i) Q[q_index[i]] = q[i];
    for (int i = 0; i < model.nu; ++i) U[u_index[i]] = u[i];
  }

  void getState(Eigen::VectorXd& q, Eigen::VectorXd& u) const {
    q.resize(model.nq);
    u.resize(model.nu);
    for (int i = 0; i < model.nq; ++i) q[i] = state.getQ()[q_index[i]];
    for (int i = 0; i < model.nu; ++i) u[i] = state.getU()[u_index[i]];
  }

  Eigen::VectorXd toInhouse(const Vector& v) const {
    Eigen::VectorXd out(model.nu);
    for (int i = 0; i < model.nu; ++i) out[i] = v[u_index[i]];
    return out;
  }

  double kineticEnergy() {
    system.realize(state, SimTK::Stage::Velocity);
    return system.calcKineticEnergy(state);
  }

  double potentialEnergy() {
    system.realize(state, SimTK::Stage::Dynamics);
    return system.calcPotentialEnergy(state);
  }

  // The sample at t of state s, through the shared sampler.
  void sample(Trajectory& tr, double t, const State& s);

  std::vector<Pose> poses() {
    system.realize(state, SimTK::Stage::Position);
    std::vector<Pose> out(model.n());
    for (int i = 0; i < model.n(); ++i) {
      const Transform& X = mobods[i].getBodyTransform(state);
      out[i].p = em::Vec3(X.p()[0], X.p()[1], X.p()[2]);
      out[i].quat = matrixToQuat(toEigen(X.R()));
    }
    return out;
  }

  const Model& model;
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter;
  SimTK::GeneralForceSubsystem forces;
  std::vector<MobilizedBody> mobods;  // internal order
  std::vector<Damper> dampers;  // and drives
  std::vector<PointDamper> point_dampers;
  SimTK::Measure::Integrate dissipated;  // W_diss; empty handle without dampers
  State state;
  std::vector<int> q_index, u_index;  // Simbody index of in-house q[i], u[i]
  JointControlForce* control = nullptr;  // a joint controller, owned by `forces`, or null
  bool tracksWork() const { return !dampers.empty() || !point_dampers.empty() || control; }
  LoopMeter meter;                     // a mechanism's violation at the samples, by our g(q)
};

SimbodySystem::SimbodySystem(const Model& m) : impl_(std::make_unique<Impl>(m)) {}
SimbodySystem::~SimbodySystem() = default;

void SimbodySystem::setState(const Eigen::VectorXd& q, const Eigen::VectorXd& u) { impl_->setState(q, u); }
void SimbodySystem::getState(Eigen::VectorXd& q, Eigen::VectorXd& u) const { impl_->getState(q, u); }

Eigen::MatrixXd SimbodySystem::massMatrix() {
  impl_->system.realize(impl_->state, SimTK::Stage::Position);
  SimTK::Matrix M;
  impl_->matter.calcM(impl_->state, M);
  const std::vector<int>& map = impl_->u_index;
  const int n = impl_->model.nu;
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = M(map[i], map[j]);
  return A;
}

Eigen::VectorXd SimbodySystem::rhs() {
  auto& I = *impl_;
  I.system.realize(I.state, SimTK::Stage::Dynamics);
  const Vector& f_mob = I.system.getMobilityForces(I.state, SimTK::Stage::Dynamics);
  const SimTK::Vector_<SimTK::SpatialVec>& f_body = I.system.getRigidBodyForces(I.state, SimTK::Stage::Dynamics);
  Vector zero(I.state.getNU(), 0.0), residual;
  I.matter.calcResidualForceIgnoringConstraints(I.state, f_mob, f_body, zero, residual);
  return -I.toInhouse(residual);
}

Eigen::VectorXd SimbodySystem::udot() {
  impl_->system.realize(impl_->state, SimTK::Stage::Acceleration);
  return impl_->toInhouse(impl_->state.getUDot());
}

double SimbodySystem::kineticEnergy() { return impl_->kineticEnergy(); }
double SimbodySystem::potentialEnergy() { return impl_->potentialEnergy(); }

std::vector<Pose> SimbodySystem::poses() { return impl_->poses(); }

namespace {

// Simbody's schemes: their ids, the order of its row's schemes (simbodyEngine).
enum class SimbodyScheme { RkMerson, Rk3, CPodes, Count };

// Simbody's scheme of a run, by its id.
std::unique_ptr<SimTK::Integrator> makeIntegrator(const RunSpec& spec, const SimTK::MultibodySystem& system) {
  switch (static_cast<SimbodyScheme>(schemeIndex(spec.engine(), spec.integrator))) {
    case SimbodyScheme::RkMerson: return std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system);
    case SimbodyScheme::Rk3: return std::make_unique<SimTK::RungeKutta3Integrator>(system);
    case SimbodyScheme::CPodes: return std::make_unique<SimTK::CPodesIntegrator>(system);
    case SimbodyScheme::Count: break;
  }
  throw std::logic_error(std::string("no Simbody integrator for ") + integratorName(spec.integrator));
}

}  // namespace

void SimbodySystem::Impl::sample(Trajectory& tr, double t, const State& s) {
  state = s;
  Eigen::VectorXd q, u;
  getState(q, u);
  const double T = kineticEnergy();
  const double W = tracksWork() ? dissipated.getValue(state) : 0.0;
  appendSample(tr, model, t, q.data(), u.data(), poses(), {T + potentialEnergy(), T, W});
  if (!model.loops.empty()) {
    tr.has_loops = true;
    meter.record(q.data(), u.data(), tr.loops);
  }
}

namespace {
// A step that collapsed (Trajectory's StepUnderflow), apart from the engine's own errors.
struct StepUnderflowError : std::runtime_error {
  explicit StepUnderflowError(double step) : std::runtime_error("step underflow"), h(step) {}
  double h;
};
}  // namespace

Trajectory SimbodySystem::simulate(const CheckedRunSpec& run, const SampleObserver& observe) {
  const RunSpec& spec = run;
  const long n_out = outputIntervals(spec.t_end, spec.output_dt);
  auto& I = *impl_;
  std::unique_ptr<SimTK::Integrator> integ = makeIntegrator(spec, I.system);
  integ->setAccuracy(spec.tol);
  Trajectory tr = makeTrajectory(I.model, spec);
  // Start from t = 0 whatever an earlier run left in the state.
  I.state = I.system.getDefaultState();
  setState(I.model.q0(), I.model.u0());
  I.system.realize(I.state, SimTK::Stage::Acceleration);
  I.sample(tr, 0.0, I.state);
  double cpu = 0;
  EngineMessages said;  // CPodes prints its errors on stderr, one per failed call
  std::clock_t c0 = 0;    // the interval's start: a failing interval's time counts too
  // A sampled controller: Simbody stops at each of its instants t_c (a
  // scheduled event it does not step past), where the held torques jump.
  const bool sampled = I.control && I.control->loop().sampled();
  long c = 0;
  double t_c = std::numeric_limits<double>::infinity();
  if (sampled) I.control->sample(I.state), t_c = I.control->loop().period();
  try {
    integ->initialize(I.state);
    for (long k = 1; k <= n_out; ++k) {
      const double t_out = k * spec.output_dt;
      said.resume();
      c0 = std::clock();
      // The first stepTo may return early (at an event or the first step): loop until t_out.
      while (integ->getTime() < t_out * (1 - 1e-14)) {
        const SimTK::Integrator::SuccessfulStepStatus st = integ->stepTo(t_out, t_c);
        if (sampled && integ->getTime() >= t_c * (1 - 1e-14)) {  // at t_c: sample, hold, restart from the advanced state there
          SimTK::State& at = integ->updAdvancedState();
          I.control->sample(at);
          at.invalidateAllCacheAtOrAbove(SimTK::Stage::Dynamics);
          integ->reinitialize(SimTK::Stage::Dynamics, false);
          t_c = static_cast<double>(++c + 1) * I.control->loop().period();
        }
        if (st == SimTK::Integrator::EndOfSimulation) throw std::runtime_error("integrator ended the simulation early");
        // The budgets every run keeps (issue 73, item 11: CPodes at tol 1e-12 on a flat
        // parallelogram ran past 60 s): the steps of MethodOptions::max_steps, and a step
        // no longer than 1e-14 of the time, the in-house adaptive runs' underflow (h = 0: none since a restart at a control sample).
        if (static_cast<double>(integ->getNumStepsTaken()) > spec.options.max_steps)
          throw std::runtime_error("more than " + gnum(spec.options.max_steps) + " steps (the step budget; a plan's max_steps raises it)");
        if (const double h = integ->getPreviousStepSizeTaken(); integ->getNumStepsTaken() > 0 && h > 0 && h < 1e-14 * std::max(1.0, integ->getTime()))
          throw StepUnderflowError(h);
      }
      cpu += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
      said.pause();
      I.sample(tr, t_out, integ->getState());
      if (observe) observe(t_out);
    }
  } catch (const StepUnderflowError& e) {
    if (c0) cpu += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    markFailed(tr, integ->getTime(), Failure::StepUnderflow, "Simbody's step fell to " + gnum(e.h, 3) + " s");
  } catch (const std::exception& e) {
    if (c0) cpu += static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    markFailed(tr, integ->getTime(), Failure::Engine, "Simbody: " + oneLine(e.what()));
  }
  said.pause();
  if (const std::string line = said.summary(std::string("Simbody's ") + integratorName(spec.integrator)); !line.empty()) {
    if (tr.failed()) tr.failure += "; " + line;
    else std::fprintf(stderr, "%s\n", line.c_str());
  }
  tr.run_time_s = cpu;
  tr.steps = integ->getNumStepsTaken();
  tr.rhs_evals = integ->getNumRealizations();
  return tr;
}

namespace {

// Simbody's equations at any state, for crosscheck and `equations`.
class SimbodyModel : public EngineModel {
 public:
  explicit SimbodyModel(const Model& m) : ref_(m) {}
  EngineEquations at(const Eigen::VectorXd& q, const Eigen::VectorXd& u) override {
    ref_.setState(q, u);
    return {ref_.massMatrix(), ref_.rhs(), ref_.udot(), ref_.kineticEnergy(), ref_.potentialEnergy()};
  }
  // setState invalidates the Position stage, so each call realizes from scratch.
  void forward(const Eigen::VectorXd& q, const Eigen::VectorXd& u) override {
    ref_.setState(q, u);
    ref_.udot();
  }

 private:
  SimbodySystem ref_;
};

}  // namespace

EngineRow simbodyEngine() {
  EngineRow r;
  r.info.name = "simbody";
  r.info.summary = "Simbody's own O(n) recursive dynamics: the independent engine";
  r.info.schemes.resize(static_cast<size_t>(SimbodyScheme::Count));  // each at its id
  r.info.schemes[static_cast<size_t>(SimbodyScheme::RkMerson)] = {"rkmerson", false, "Simbody Runge-Kutta-Merson, adaptive", "v"};
  r.info.schemes[static_cast<size_t>(SimbodyScheme::Rk3)] = {"rk3", false, "Simbody Runge-Kutta 3, adaptive", "<"};
  r.info.schemes[static_cast<size_t>(SimbodyScheme::CPodes)] = {"cpodes", false, "Simbody CPodes (implicit BDF), adaptive", ">"};
  r.info.fixed_scheme = "rkmerson";
  r.info.adaptive_scheme = "rkmerson";
  r.info.max_tol = 1.0;  // Simbody asserts (SIGABRT) on an accuracy >= 1
  r.info.colour = "tab:gray";
  r.info.roles.reference = true;  // the reference of every comparison of a tree, when none is named
  r.code.simulate = [](const Model& m, const CheckedRunSpec& spec, const SampleObserver& observe) {
    return SimbodySystem(m).simulate(spec, observe);
  };
  r.code.model = [](const Model& m) -> std::unique_ptr<EngineModel> { return std::make_unique<SimbodyModel>(m); };
  r.code.forward_call = "Simbody realize(Acceleration)";
  // Every closure kind, point spring-damper and drive maps (addLoop, addPointSpring, addDrive).
  r.code.mechanism_refusal = [](const Model&) { return std::string(); };
  r.code.version = [] { return std::string(EM_SIMBODY_VERSION); };
  return r;
}

}  // namespace em
