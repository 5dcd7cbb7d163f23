// ODE 0.16 (libode-dev, double precision) as an engine, row `ode`
// (docs/reference-engines.md):
//
// Maximal coordinates: every body is an ODE body (its frame ours, at its CM,
// the full inertia), every joint an ODE joint between it and its parent (the
// static world for roots), made with every body at our zero configuration:
//   revolute: hinge; prismatic: slider; universal: universal (axis 1 fixed in
//   the parent, axis 2 in the body); ball and gimbal: ball (a gimbal's angles
//   are read back from the relative rotation); free: no joint.
// ODE holds the joints by constraint forces, its drift fed back at ERP 0.2 and
// the constraints softened by CFM 1e-10 (its defaults in double precision,
// kept and stated in every report). Our coordinates and speeds are read back
// from the bodies' relative poses and velocities (jointCoordinates,
// jointSpeeds); how far each joint's two points have drifted apart is the
// run's constraint violation (max_joint_separation). Springs and dampers are
// joint torques (a slider's: forces at the joint point) from the state at a
// step's start, held over it: ODE has no joint springs. ODE gives no
// accelerations at a state, so it has no crosscheck rows and no u' method.
//
// Mechanisms (docs/reference-engines.md, "Mechanisms"): a loop is one more
// ODE joint between its two bodies (the static world for the ground), made at
// the assembled initial state: a ball closure a ball joint at the point, a
// hinge a hinge about axis_a, a weld a fixed joint (dJointSetFixed keeps the
// relative pose it finds). Loops hold as the tree's joints do, by constraint
// forces at ERP and CFM, and their points' separation counts in the run's
// max_joint_separation. Point spring-dampers are forces at their points, and
// drives (a constant generalized force) joint torques, both from the state at
// a step's start, held over it as the joint springs are.
#include "solver/applied_forces.hpp"
#include "solver/mechanism/loops.hpp"
//
// Two schemes: ode-step (dWorldStep: a direct solve of the constraint forces,
// then semi-implicit Euler) and ode-quickstep (dWorldQuickStep: 20 iterations
// of projected Gauss-Seidel, its default, in place of the direct solve).
#include <ode/ode.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <mutex>
#include <stdexcept>
#include <string>

#include "reference/engine.hpp"
#include "reference/fixed_step.hpp"
#include "solver/formation.hpp"
#include "solver/joint.hpp"

static_assert(sizeof(dReal) == sizeof(double), "ODE must be its double-precision build (libode-dev's)");

namespace em {

namespace {

// ODE's messages (warnings) go to stderr unless handled: none may reach
// eigenmass's output. The last one is kept; a step that raises one ends the
// run with it (a construction's, such as a universal joint's first axis set
// before its second, are dropped).
thread_local std::string g_message;
void keepMessage(int, const char* format, va_list args) {
  char text[256];
  std::vsnprintf(text, sizeof text, format, args);
  g_message = text;
}

void initOde() {
  static std::once_flag once;
  std::call_once(once, [] {
    dInitODE2(0);
    dSetMessageHandler(keepMessage);
  });
}

Vec3 ev(const dReal* v) { return {v[0], v[1], v[2]}; }
Mat3 rotationOf(dBodyID b) {
  const dReal* q = dBodyGetQuaternion(b);  // [w, x, y, z]
  return quatToMatrix(Vec4(q[0], q[1], q[2], q[3]));
}

// Our zero configuration: angles and slides 0, quaternions the identity.  // (nq)
Eigen::VectorXd zeroConfiguration(const Model& m) {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(m.nq);
  for (const Body& b : m.bodies)
    if (const int at = jointQuat(b.joint.type); at >= 0) q[b.iq + at] = 1;
  return q;
}

// A joint kind in ODE, the one mapping of kinds: the ODE joint between a
// body and its parent (none for a free joint), or Missing where ODE 0.16 has
// none (its plane-2D joint holds a body to the world's z = 0 plane only, not
// to a parent's plane): such a scene is refused for ODE before any run.
enum class OdeJoint { Hinge, Slider, Universal, Ball, None, Missing };

OdeJoint odeJoint(JointType t) {
  switch (t) {
    case JointType::Revolute: return OdeJoint::Hinge;
    case JointType::Prismatic: return OdeJoint::Slider;
    case JointType::Universal: return OdeJoint::Universal;
    case JointType::Ball:
    case JointType::Gimbal: return OdeJoint::Ball;  // a gimbal's angles are read back from the relative rotation
    case JointType::Free: return OdeJoint::None;
    case JointType::Planar: return OdeJoint::Missing;
  }
  return OdeJoint::Missing;
}

// What of a mechanism ODE's row does not map, or "": every closure kind maps
// to an ODE joint; a drive on a free joint has no joint to act through.
std::string odeMechanismRefusal(const Model& m) {
  for (const Body& b : m.bodies)
    if (b.joint.torque.size() > 0 && b.joint.type == JointType::Free)
      return "the drive on body '" + b.name + "': a free joint is no ODE joint, and its mixed forces and torques are not mapped";
  return "";
}

// Why ODE cannot take `m` (a joint kind it has no joint for), or "".
std::string odeRefusal(const Model& m) {
  for (const Body& b : m.bodies)
    if (odeJoint(b.joint.type) == OdeJoint::Missing)
      return std::string("ODE 0.16 has no ") + jointTypeName(b.joint.type) + " joint between two bodies (body '" + b.name +
             "')";
  return "";
}

// Why ODE's stops cannot take `m`'s joint limits, or "": a hinge's and a
// slider's map (dParamLoStop, dParamHiStop, dParamBounce); a hinge's angle
// lives in [-pi, pi], so a stop beyond is none of ODE's.
std::string odeLimitsRefusal(const Model& m) {
  for (const Body& b : m.bodies) {
    if (!b.joint.limits) continue;
    const OdeJoint k = odeJoint(b.joint.type);
    if (k != OdeJoint::Hinge && k != OdeJoint::Slider)
      return std::string("the limits of body '") + b.name + "': ODE's stops are mapped on hinges and sliders, not on a " + jointTypeName(b.joint.type) + " joint";
    if (k == OdeJoint::Hinge && (b.joint.limits->lower[0] < -M_PI || b.joint.limits->upper[0] > M_PI))
      return "the limits of body '" + b.name + "': ODE's hinge angle lives in [-pi, pi], and a stop beyond it is none of ODE's";
  }
  return "";
}

// A body's frame and motion as ODE keeps them, world frame.
struct BodyState {
  Mat3 R = Mat3::Identity();
  Vec3 r = Vec3::Zero(), v = Vec3::Zero(), w = Vec3::Zero();
};

// The Model as ODE bodies and joints in one world.
class OdeSystem {
 public:
  explicit OdeSystem(const Model& m) : m_(m), body_(m.n()), joint_(m.n(), nullptr), last_q_(m.q0()) {
    initOde();
    world_ = dWorldCreate();
    dWorldSetGravity(world_, m.gravity.x(), m.gravity.y(), m.gravity.z());
    for (int i = 0; i < m.n(); ++i) {
      const Body& b = m.bodies[i];
      body_[i] = dBodyCreate(world_);
      dMass mass;
      dMassSetParameters(&mass, b.mass, 0, 0, 0, b.J(0, 0), b.J(1, 1), b.J(2, 2), b.J(0, 1), b.J(0, 2), b.J(1, 2));
      dBodySetMass(body_[i], &mass);
    }
    setBodies(zeroConfiguration(m), Eigen::VectorXd::Zero(m.nu));
    for (int i = 0; i < m.n(); ++i) joint_[i] = makeJoint(i);
    setJointStops(m);
    setBodies(m.q0(), m.u0());  // assembled: every loop's points meet (io/, assembleStart)
    for (const Loop& l : m.loops) makeLoopJoint(l);
    g_message.clear();
  }
  ~OdeSystem() { dWorldDestroy(world_); }  // its bodies and joints with it
  OdeSystem(const OdeSystem&) = delete;
  OdeSystem& operator=(const OdeSystem&) = delete;

  dWorldID world() const { return world_; }

  // Every stop's dParamStopERP and dParamStopCFM.
  void softenStops(double erp, double cfm) {
    for (int i = 0; i < m_.n(); ++i) {
      if (!m_.bodies[i].joint.limits) continue;
      const bool hinge = odeJoint(m_.bodies[i].joint.type) == OdeJoint::Hinge;
      for (const auto& [param, value] : {std::pair{dParamStopERP, erp}, std::pair{dParamStopCFM, cfm}})
        (hinge ? dJointSetHingeParam : dJointSetSliderParam)(joint_[i], param, value);
    }
  }


  // Our state into ODE's bodies (the in-house kinematics places them).
  void setBodies(const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
    Workspace ws(m_);
    formKinematics(m_, q.data(), u.data(), ws);
    for (int i = 0; i < m_.n(); ++i) {
      const Vec4 quat = matrixToQuat(ws.R[i]);
      const dQuaternion dq = {quat[0], quat[1], quat[2], quat[3]};
      dBodySetPosition(body_[i], ws.r[i].x(), ws.r[i].y(), ws.r[i].z());
      dBodySetQuaternion(body_[i], dq);
      dBodySetLinearVel(body_[i], ws.v[i].x(), ws.v[i].y(), ws.v[i].z());
      dBodySetAngularVel(body_[i], ws.omega[i].x(), ws.omega[i].y(), ws.omega[i].z());
    }
  }

  // ODE's bodies as our (q, u), and the largest joint separation (m) there.
  double getState(Eigen::VectorXd& q, Eigen::VectorXd& u) {
    double apart = 0;
    for (int i = 0; i < m_.n(); ++i) {
      const Body& b = m_.bodies[i];
      const BodyState s = state(i), p = b.parent < 0 ? BodyState{} : state(b.parent);
      const Vec3 jp = p.r + p.R * b.joint.in_parent, jb = s.r + s.R * b.joint.in_body;  // the joint's two points
      const Vec3 x = p.R.transpose() * (jb - jp);
      const Vec3 jp_dot = p.v + p.w.cross(jp - p.r), jb_dot = s.v + s.w.cross(jb - s.r);
      const Vec3 xdot = p.R.transpose() * (jb_dot - jp_dot - p.w.cross(jb - jp));
      jointCoordinates(b.joint, p.R.transpose() * s.R, x, last_q_.data() + b.iq, q.data() + b.iq);
      jointSpeeds(b.joint, q.data() + b.iq, p.R.transpose() * (s.w - p.w), xdot, u.data() + b.iu);
      apart = std::max(apart, jointSeparation(b.joint, x));
    }
    for (const Loop& l : m_.loops) {
      const Point a = at(l.a);
      apart = std::max(apart, loopPointGap(l, a.p, at(l.b).p, a.body ? rotationOf(a.body) : Mat3::Identity()));
    }
    last_q_ = q;
    return apart;
  }

  // The joint springs', dampers' and drives' generalized forces
  // Q = -k (q - q_rest) - c u + tau at (q, u), as torques (a slider's: forces
  // at the joint point) on the body and the opposite on its parent:
  // Q = E^T f for f = E (E^T E)^-1 Q.
  // A joint controller's held torques `control` (nu, or empty) join them (theory.md §18).
  void addJointForces(const Eigen::VectorXd& q, const Eigen::VectorXd& u, const Eigen::VectorXd& control) {
    for (int i = 0; i < m_.n(); ++i) {
      const Body& b = m_.bodies[i];
      const bool driven = b.joint.torque.size() > 0, controlled = b.joint.control.has_value() && control.size();
      if (!b.joint.has_spring && !driven && !controlled) continue;  // ball and free joints carry no spring nor control (io/scene_json.cpp)
      const int nu = b.nu();
      Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> Q = Eigen::VectorXd::Zero(nu);
      if (b.joint.has_spring) {
        const Spring& sp = b.joint.spring;
        for (int k = 0; k < nu; ++k) Q[k] -= sp.k[k] * (q[b.iq + k] - sp.q_rest[k]) + sp.c[k] * u[b.iu + k];
      }
      if (driven) Q += b.joint.torque;
      if (controlled) Q += control.segment(b.iu, nu);
      const Mat3 Rp = b.parent < 0 ? Mat3::Identity() : rotationOf(body_[b.parent]);
      Axes E;
      worldAxes(b.joint, Rp, q.data() + b.iq, E);  // world frame
      const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3> EtE = E.transpose() * E;
      const Vec3 f = E * EtE.ldlt().solve(Q);
      applyPair(i, f, jointNt(b.joint.type) > 0);
    }
  }

  // The point spring-dampers' tensions k (l - length) + c l' along the line
  // from a's point to b's, pulling the points together (theory.md §15).
  void addPointSpringForces() {
    for (const PointSpring& s : m_.point_springs) {
      const Point a = at(s.a), b = at(s.b);
      const Vec3 f = pointSpringForce(s, a.p, a.v, b.p, b.v);  // on a; -f on b
      if (a.body) dBodyAddForceAtPos(a.body, f.x(), f.y(), f.z(), a.p.x(), a.p.y(), a.p.z());
      if (b.body) dBodyAddForceAtPos(b.body, -f.x(), -f.y(), -f.z(), b.p.x(), b.p.y(), b.p.z());
    }
  }

  void poses(std::vector<Pose>& out) const {
    out.resize(m_.n());
    for (int i = 0; i < m_.n(); ++i) {
      const dReal* qq = dBodyGetQuaternion(body_[i]);
      out[i] = {ev(dBodyGetPosition(body_[i])), Vec4(qq[0], qq[1], qq[2], qq[3]).normalized()};
    }
  }

  // T of ODE's bodies; V of gravity on them, and of the springs at q (ours, the same state).
  void energies(const Eigen::VectorXd& q, double& T, double& V) const {
    T = V = 0;
    for (int i = 0; i < m_.n(); ++i) {
      const Body& b = m_.bodies[i];
      const BodyState s = state(i);
      T += 0.5 * (b.mass * s.v.squaredNorm() + s.w.dot(s.R * b.J * s.R.transpose() * s.w));
      V -= b.mass * m_.gravity.dot(s.r);
      if (b.joint.has_spring)
        for (int k = 0; k < b.nu(); ++k) V += 0.5 * b.joint.spring.k[k] * std::pow(q[b.iq + k] - b.joint.spring.q_rest[k], 2);
    }
    for (const PointSpring& s : m_.point_springs) {
      const double e = (at(s.b).p - at(s.a).p).norm() - s.length;
      V += 0.5 * s.k * e * e;
    }
  }

 private:
  // A loop's or point spring's point as ODE moves it: its body (nullptr: the static world), position and velocity.
  struct Point {
    dBodyID body = nullptr;
    Vec3 p = Vec3::Zero(), v = Vec3::Zero();
  };
  Point at(const Attachment& x) const {
    if (x.body < 0) return {nullptr, x.point, Vec3::Zero()};
    const BodyState s = state(x.body);
    const Vec3 arm = s.R * x.point;
    return {body_[x.body], s.r + arm, s.v + s.w.cross(arm)};
  }

  // A closure as an ODE joint between its two bodies, made where its points meet.
  void makeLoopJoint(const Loop& l) {
    const Point a = at(l.a), b = at(l.b);
    const Vec3 axis = (a.body ? rotationOf(a.body) : Mat3::Identity()) * l.axis_a;  // world frame
    dJointID j = nullptr;
    switch (l.type) {
      case LoopType::Ball:
        j = dJointCreateBall(world_, nullptr);
        dJointAttach(j, a.body, b.body);
        dJointSetBallAnchor(j, a.p.x(), a.p.y(), a.p.z());
        break;
      case LoopType::Hinge:
        j = dJointCreateHinge(world_, nullptr);
        dJointAttach(j, a.body, b.body);
        dJointSetHingeAnchor(j, a.p.x(), a.p.y(), a.p.z());
        dJointSetHingeAxis(j, axis.x(), axis.y(), axis.z());
        break;
      case LoopType::Weld:  // b's pose relative to a's as it is now: rel, and the points met
        j = dJointCreateFixed(world_, nullptr);
        dJointAttach(j, a.body, b.body);
        dJointSetFixed(j);
        break;
      case LoopType::Universal: {  // axis 1 turns with body 1 (a), axis 2 with body 2 (b)
        const Vec3 axis2 = (b.body ? rotationOf(b.body) : Mat3::Identity()) * l.axis_b;
        j = dJointCreateUniversal(world_, nullptr);
        dJointAttach(j, a.body, b.body);
        dJointSetUniversalAnchor(j, a.p.x(), a.p.y(), a.p.z());
        dJointSetUniversalAxis1(j, axis.x(), axis.y(), axis.z());
        dJointSetUniversalAxis2(j, axis2.x(), axis2.y(), axis2.z());
        break;
      }
      case LoopType::Slider:  // along axis_a, b's turn relative to a's as it is now (rel)
        j = dJointCreateSlider(world_, nullptr);
        dJointAttach(j, a.body, b.body);
        dJointSetSliderAxis(j, axis.x(), axis.y(), axis.z());
        break;
    }
  }

  BodyState state(int i) const {
    return {rotationOf(body_[i]), ev(dBodyGetPosition(body_[i])), ev(dBodyGetLinearVel(body_[i])),
            ev(dBodyGetAngularVel(body_[i]))};
  }

  // Body i's joint to its parent, made at the configuration the bodies are in.
  dJointID makeJoint(int i) {
    const Body& b = m_.bodies[i];
    const dBodyID me = body_[i], parent = b.parent < 0 ? nullptr : body_[b.parent];
    const BodyState s = state(i);
    const Vec3 o = s.r + s.R * b.joint.in_body;       // the joint point
    const Mat3 Rp = b.parent < 0 ? Mat3::Identity() : rotationOf(parent);
    const Vec3 a0 = Rp * b.joint.axis[0], a1 = s.R * b.joint.axis[1];  // world frame
    dJointID j = nullptr;
    switch (odeJoint(b.joint.type)) {
      case OdeJoint::Hinge:
        j = dJointCreateHinge(world_, nullptr);
        dJointAttach(j, parent, me);
        dJointSetHingeAnchor(j, o.x(), o.y(), o.z());
        dJointSetHingeAxis(j, a0.x(), a0.y(), a0.z());
        return j;  // its stops once every joint is made (setJointStops)
      case OdeJoint::Slider:
        j = dJointCreateSlider(world_, nullptr);
        dJointAttach(j, parent, me);
        dJointSetSliderAxis(j, a0.x(), a0.y(), a0.z());
        return j;  // its stops once every joint is made (setSliderStops)
      case OdeJoint::Universal:  // axis 1 fixed in body 1 (the parent), axis 2 in body 2
        j = dJointCreateUniversal(world_, nullptr);
        dJointAttach(j, parent, me);
        dJointSetUniversalAnchor(j, o.x(), o.y(), o.z());
        dJointSetUniversalAxis1(j, a0.x(), a0.y(), a0.z());
        dJointSetUniversalAxis2(j, a1.x(), a1.y(), a1.z());
        return j;
      case OdeJoint::Ball:
        j = dJointCreateBall(world_, nullptr);
        dJointAttach(j, parent, me);
        dJointSetBallAnchor(j, o.x(), o.y(), o.z());
        return j;
      case OdeJoint::None: return nullptr;
      case OdeJoint::Missing: break;
    }
    throw std::invalid_argument("ode: " + odeRefusal(m_));  // refused before any run (EngineCode::refusal)
  }

  // A hinge's or slider's stops (docs/reference-engines.md, "Joint limits"):
  // dParamLoStop and dParamHiStop at the limits, dParamBounce the restitution
  // e; their ERP and CFM are the world's (ODE's defaults for dParamStopERP, dParamStopCFM).
  static void setStops(dJointID j, void (*set)(dJointID, int, dReal), const JointLimits& l) {
    set(j, dParamLoStop, l.lower[0]);
    set(j, dParamHiStop, l.upper[0]);
    set(j, dParamBounce, l.restitution);
  }

  // A hinge's or slider's stops in ODE's own angle or position, whose sign
  // against our q it has from how its bodies attach: a slider's read at
  // q = 0.5 on that coordinate alone, the others at zero (where the joints were made).
  void setJointStops(const Model& m) {
    for (int i = 0; i < m.n(); ++i) {
      const Body& b = m.bodies[i];
      if (!b.joint.limits) continue;
      const bool hinge = odeJoint(b.joint.type) == OdeJoint::Hinge;
      Eigen::VectorXd q = zeroConfiguration(m);
      q[b.iq] = 0.5;
      setBodies(q, Eigen::VectorXd::Zero(m.nu));
      // ODE tests a hinge's stops on its internal angle: ours where the hinge is
      // attached to the world (ODE then keeps it reversed), the opposite between two
      // bodies (measured: tests/reference/test_limits_engines.cpp); a slider's on the position its getter returns.
      const double read = hinge ? (b.parent < 0 ? 1.0 : -1.0) : dJointGetSliderPosition(joint_[i]);
      JointLimits l = *b.joint.limits;
      if (read < 0) l.lower[0] = -b.joint.limits->upper[0], l.upper[0] = -b.joint.limits->lower[0];
      setStops(joint_[i], hinge ? dJointSetHingeParam : dJointSetSliderParam, l);
    }
  }

  // f on body i and -f on its parent: torques, or forces at the joint point (slides).
  void applyPair(int i, const Vec3& f, bool force) {
    const Body& b = m_.bodies[i];
    const BodyState s = state(i);
    const Vec3 o = s.r + s.R * b.joint.in_body;
    for (int side = 0; side < 2; ++side) {
      const dBodyID on = side == 0 ? body_[i] : (b.parent < 0 ? nullptr : body_[b.parent]);
      if (!on) continue;
      const Vec3 g = side == 0 ? f : Vec3(-f);
      if (force) dBodyAddForceAtPos(on, g.x(), g.y(), g.z(), o.x(), o.y(), o.z());
      else dBodyAddTorque(on, g.x(), g.y(), g.z());
    }
  }

  const Model& m_;
  dWorldID world_ = nullptr;
  std::vector<dBodyID> body_;    // internal order
  std::vector<dJointID> joint_;  // body i's joint to its parent (nullptr: free)
  Eigen::VectorXd last_q_;       // (nq): the last read-back, for angle branches
};

// ODE's schemes: their ids, the order of its row's schemes (odeEngine).
enum OdeScheme { kOdeStep, kOdeQuickstep, kOdeSchemes };

// dWorldStep or dWorldQuickStep at exactly dt, one evaluation a step.
class OdeStepper : public FixedStepEngine {
 public:
  OdeStepper(const Model& m, const RunSpec& spec)
      : m_(m), ode_(m), dt_(spec.dt), quick_(schemeIndex(spec.engine(), spec.integrator) == kOdeQuickstep),
        q_(m.q0()), u_(m.u0()) {
    const MethodInfo& row = info(spec.method);
    dWorldSetERP(ode_.world(), row.param("ode_erp", spec.options));
    dWorldSetCFM(ode_.world(), row.param("ode_cfm", spec.options));
    for (const Body& b : m.bodies) joint_forces_ = joint_forces_ || b.joint.has_spring || b.joint.torque.size() > 0 || b.joint.control;
    if (!m.limited.empty()) ode_.softenStops(row.param("ode_stop_erp", spec.options), row.param("ode_stop_cfm", spec.options));
  }
  std::string step() override {
    if (joint_forces_) {
      ode_.getState(q_, u_);
      ode_.addJointForces(q_, u_, control_);
    }
    ode_.addPointSpringForces();
    const int ok = quick_ ? dWorldQuickStep(ode_.world(), dt_) : dWorldStep(ode_.world(), dt_);
    ++evaluations_;
    if (!ok) return "ODE: the step could not allocate its working memory";
    std::string said;
    said.swap(g_message);
    return said.empty() ? "" : "ODE: " + said;
  }
  long evaluations() const override { return evaluations_; }
  void applyControl(const Eigen::VectorXd& tau) override { control_ = tau; }
  void state(Eigen::VectorXd& q, Eigen::VectorXd& u) override { apart_ = ode_.getState(q, u); }
  double jointSeparation() const override { return apart_; }
  void sample(std::vector<Pose>& poses, double& kinetic, double& potential) override {
    apart_ = ode_.getState(q_, u_);
    ode_.poses(poses);
    ode_.energies(q_, kinetic, potential);
  }
  // P (dampers' power less the drives', theory.md eq. (M6)) at the read-back
  // state; ODE gives no u', so P' = 0 (W_diss by the plain trapezoid rule:
  // second order, ODE's own error is first).
  void dissipation(double& P, double& Pdot) override {
    ode_.getState(q_, u_);
    formKinematics(m_, q_.data(), u_.data(), ws_);
    P = nonConservativePower(m_, ws_, u_.data());
    Pdot = 0;
  }

 private:
  const Model& m_;
  OdeSystem ode_;
  double dt_;
  bool quick_, joint_forces_ = false;
  Eigen::VectorXd control_;  // a joint controller's held torques (nu), empty before the first
  Eigen::VectorXd q_, u_;  // (nq), (nu): the state the springs act at
  Workspace ws_{m_};       // the read-back state's kinematics, for the point dampers' power
  double apart_ = 0;
  long evaluations_ = 0;
};

}  // namespace

EngineRow odeEngine() {
  EngineRow r;
  r.info.name = "ode";
  r.info.summary = "ODE 0.16's bodies and joints in maximal coordinates (constraint forces, ERP 0.2 and CFM 1e-10, its "
                   "defaults; springs and dampers as joint torques held over a step), fixed step (Gazebo Classic's default)";
  r.info.schemes.resize(kOdeSchemes);  // each at its id
  r.info.schemes[kOdeStep] = {"ode-step", true, "ODE's dWorldStep: constraint forces by a direct solve, then semi-implicit Euler", "v"};
  r.info.schemes[kOdeQuickstep] = {"ode-quickstep", true, "ODE's dWorldQuickStep: 20 projected Gauss-Seidel iterations in place of the solve", "^"};
  r.info.fixed_scheme = "ode-step";
  r.info.adaptive_scheme = "ode-step";  // ODE has no adaptive scheme
  r.info.colour = "navy";
  // Every joint's (a loop's too) stabilization: ODE's defaults in double precision.
  r.info.params = {
      {"ode_erp", 0.2, 0, 1, false, "ODE: error reduction parameter of every joint, a loop's too: the share of a joint's separation fed back per step (its default 0.2)"},
      {"ode_cfm", 1e-10, 0, 1, false, "ODE: constraint force mixing of every joint, a loop's too (its default in double precision 1e-10)"},
      {"ode_stop_erp", 0.2, 0, 1, false, "ODE: its joint stops' dParamStopERP (its default, the world's at creation: 0.2)", nullptr, false, true},
      {"ode_stop_cfm", 1e-10, 0, 1, false, "ODE: its joint stops' dParamStopCFM (its default, the world's at creation: 1e-10)", nullptr, false, true}};
  r.code.simulate = simulateFixedStep<OdeStepper>;
  r.code.limits_refusal = odeLimitsRefusal;
  r.code.scene_note = [](const Model& m) -> std::string {
    return m.limited.empty() ? "" : "joint limits: ODE's hinge and slider stops (dParamLoStop, dParamHiStop), dParamBounce = e, "
                                    "dParamStopERP and dParamStopCFM ode_stop_erp, ode_stop_cfm (its defaults 0.2, 1e-10)";
  };
  r.code.refusal = odeRefusal;
  r.code.mechanism_refusal = odeMechanismRefusal;
  // no model: ODE gives no accelerations at a state, and crosscheck says so
  r.code.equations_note = "ODE gives no accelerations at a state (maximal coordinates: its constraint forces exist only "
                          "inside its step): no rows here; its runs are judged by compare, with its joints' separation";
  r.code.version = [] { return std::string(dODE_VERSION); };
  return r;
}

}  // namespace em
