// Bullet 3.24 (libbullet-dev, in double precision: bullet-float64) as an
// engine, row `bullet` (docs/reference-engines.md):
//
// The Model as one btMultiBody (Featherstone, reduced coordinates), built in
// code. Bullet keeps a link's frame at its CM along its principal axes (its
// inertia is diagonal), so body i's Bullet frame is ours turned by P_i
// (J_i = P_i diag(I_i) P_i^T, ours <- Bullet's), and every vector of the
// joint is expressed in it. The ground is a fixed base at the world origin;
// a free root is the floating base instead (it must be the only root).
//   revolute, prismatic: Bullet's, angle (or slide) and speed ours;
//   universal: two revolutes through a massless link at the joint point (exact);
//   ball: spherical, its quaternion that of P^T R P, its speed the angular
//         velocity in the link frame, P^T R^T w;
//   gimbal: spherical too, R = Rx Ry Rz (q), its speed P^T R^T E(q) u;
//   free (the root): the floating base, at the CM in the P frame, its speeds
//         [w, v_CM] in the world frame, v_CM = v + (R c) x w.
// So u_B = G u (per joint, invertible away from the gimbal's lock), and
// u' = G^-1 (u'_B - g), g = G' u. Bullet exposes no mass matrix: crosscheck's
// A is Bullet's, inverted from its forward dynamics under unit forces at rest
// without gravity, and B = A u'. Springs and dampers are joint torques
// -k (q - q_rest) - c u (gimbal: mapped by G^-T), held over each step: Bullet
// has no joint springs. Its own velocity damping (0.04 on every link by
// default) is turned off.
//
// Mechanisms (docs/reference-engines.md, "Mechanisms"): a ball closure is a
// btMultiBodyPoint2Point, a hinge two (the points, and the points 1 m along
// the axes), a weld a btMultiBodyFixedConstraint holding the link frames'
// relative rotation and the points as found at the assembled start; the
// ground is the fixed base, or for a floating tree Bullet's world (no rigid
// body). Bullet's constraint solver holds them at the velocity level, its
// drift fed back at ERP 0.2 over 10 sequential-impulse iterations, its
// btContactSolverInfo defaults, kept and stated. Drives are joint torques
// (the floating base's: a force at its CM and a torque), point springs forces
// at their points (tension from the read-back state), held over a step as the
// joint springs are.
//
// Two ways to run it: `bullet` is btMultiBodyDynamicsWorld::stepSimulation at
// a fixed dt with no sub-steps: semi-implicit Euler (bullet-euler), or
// btMultiBody's own rk4 (bullet-rk4). `bullet-udot` is Bullet's u' (its
// articulated-body forward dynamics) under the in-house integrators.
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyFixedConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyPoint2Point.h>
#include <BulletDynamics/Featherstone/btMultiBodySliderConstraint.h>
#include <LinearMath/btScalar.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "reference/engine.hpp"
#include "reference/fixed_step.hpp"
#include "solver/formation.hpp"
#include "solver/joint.hpp"
#include "solver/applied_forces.hpp"
#include "solver/method.hpp"

static_assert(sizeof(btScalar) == sizeof(double), "Bullet must be its double-precision build (bullet-float64)");

namespace em {

// The closure kinds Bullet 3.24's multibody constraints express (BulletChain::closures); the others are refused by name.
const std::vector<LoopType> kBulletLoops = {LoopType::Ball, LoopType::Hinge, LoopType::Weld, LoopType::Slider};
constexpr const char* kBulletConstraints =
    "Bullet 3.24's multibody constraints (btMultiBodyPoint2Point, btMultiBodyFixedConstraint, btMultiBodySliderConstraint)";

namespace {

btVector3 bt(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
Vec3 ev(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
btQuaternion btQuat(const Mat3& R) {  // Bullet's (x, y, z, w) of the same rotation
  const Vec4 q = matrixToQuat(R);
  return {q[1], q[2], q[3], q[0]};
}
Mat3 ev(const btQuaternion& q) { return quatToMatrix(Vec4(q.w(), q.x(), q.y(), q.z())); }

// A body's principal frame: J = P diag(I) P^T, P proper (ours <- Bullet's);
// P = 1 when J is diagonal already.
struct Principal {
  Mat3 P = Mat3::Identity();
  Vec3 I = Vec3::Zero();
};
Principal principal(const Mat3& J) {
  Principal p;
  if (J.isDiagonal(0.0)) {
    p.I = J.diagonal();
    return p;
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> es(J);
  p.P = es.eigenvectors();
  if (p.P.determinant() < 0) p.P.col(2) *= -1;
  p.I = es.eigenvalues();
  return p;
}

// A spherical link's speed map at (q, w) (ball, gimbal, a free joint's
// turning): u_B = G w, g = G' w, w the joint's rotational speeds: the
// angular velocity, or, with `angle_rates`, the rates of its angles (gimbal).
void sphericalMap(const Joint& j, bool angle_rates, const Mat3& P, const double* q, const double* w, Mat3& G, Vec3& g) {
  const Mat3 Rt = relativeRotation(j, q).transpose();
  if (!angle_rates) {  // w is the angular velocity, parent frame
    G = P.transpose() * Rt;
    g.setZero();
    return;
  }
  Axes E, Edot;
  worldAxes(j, Mat3::Identity(), q, E);  // the relative angular velocity, parent frame: E w
  const Eigen::Map<const Vec3> wi(w);
  axisRates(j, E, Vec3::Zero(), E * wi, w, Edot);
  G = P.transpose() * Rt * E;
  g = P.transpose() * Rt * (Edot * wi);  // (R^T)' (E w) = -R^T [E w]x E w = 0
}

// A joint kind in Bullet, the one mapping of kinds: the one-speed links
// that carry its first speeds as they are (an axis each, in the parent's
// frame at zero coordinates, sliding or turning; massless but the last), then
// a spherical link for the rest (ball, gimbal, a free joint's turning), whose
// speeds are the angular velocity or, with `angle_rates`, Cardan angle rates.
struct BulletJoint {
  struct Scalar {
    Vec3 axis;
    bool slides;
  };
  std::vector<Scalar> scalars;
  bool spherical = false, angle_rates = false;
  bool floats = false;  ///< as the only root, it is the floating base instead
};

BulletJoint bulletJoint(const Joint& j) {
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  switch (j.type) {
    case JointType::Revolute: return {{{j.axis[0], false}}};
    case JointType::Prismatic: return {{{j.axis[0], true}}};
    case JointType::Universal: return {{{j.axis[0], false}, {j.axis[1], false}}};  // through a massless link (exact)
    case JointType::Planar: return {{{j.axis[0], true}, {j.axis[1], true}, {j.axis[0].cross(j.axis[1]), false}}};
    case JointType::Ball: return {{}, true};
    case JointType::Gimbal: return {{}, true, true};
    case JointType::Free: return {{{x, true}, {y, true}, {z, true}}, true, false, true};
  }
  throw std::logic_error("Bullet: a joint kind without a mapping");
}

// Body i in the btMultiBody: its joint's links (bulletJoint), or the floating base.
struct BulletLink {
  int first = -1, link = -1;  // its first and its own (last) Bullet link; -1: the floating base
  int dof = 0;                // its first speed in Bullet's order: [base w, v_CM] (6), then the links'
  int scalars = 0;            // one-speed links, the first of its speeds as they are
  bool spherical = false;     // then a spherical link for the rest
  BulletJoint joint;
  Principal frame;
};

// The Model as a btMultiBody, and the map between our state and Bullet's.
class BulletChain {
 public:
  explicit BulletChain(const Model& m);

  btMultiBody& body() { return *mb_; }
  int firstSpeed() const { return floating_ ? 0 : 6; }  // Bullet's speeds used: [first, 6 + link dofs)
  int speeds() const { return 6 + mb_->getNumDofs() - firstSpeed(); }

  // Our (q, u), internal order, into Bullet's state.
  void setState(const double* q, const double* u);
  // Bullet's state as our (q, u); angles on the branch nearest the last read (jointCoordinates).
  void getState(Eigen::VectorXd& q, Eigen::VectorXd& u);
  // Our u' at (q, u), the state last set: Bullet's forward dynamics under
  // gravity and the springs and dampers.  // udot: (nu)
  void forwardDynamics(const double* q, const double* u, double* udot);
  // Gravity, and the springs', dampers' and drives' torques at (q, u), added
  // to Bullet's forces, with a joint controller's held torques (nu, or empty).
  void addGravity();
  void addJointTorques(const double* q, const double* u, const Eigen::VectorXd& control = Eigen::VectorXd());
  // The point spring-dampers' forces at their points, tensions at (q, u), added to Bullet's forces.
  void addPointSpringForces(const double* q, const double* u);
  // The mechanism's closures as Bullet's constraints, made at the state the chain is in (assembled).
  std::vector<std::unique_ptr<btMultiBodyConstraint>> closures();
  // The joint limits as Bullet's btMultiBodyJointLimitConstraint on one-speed links (revolute, prismatic).
  std::vector<std::unique_ptr<btMultiBodyConstraint>> stops();
  // Bullet's accelerations with the forces added ([w', v'_CM] of the base, the links'), forces cleared after.
  const double* solve();
  // Bullet's mass matrix in its speeds from firstSpeed(), at the state last set (then set again).  // (speeds^2)
  Eigen::MatrixXd massMatrix(const double* q, const double* u);
  // G (u_B = G u at q): Bullet's speeds from firstSpeed() by rows, ours by columns. Its rate G' u
  // is not needed here: u' comes through ours(), A = G^T M G needs G alone.
  void speedMap(const double* q, const double* u, Eigen::MatrixXd& G) const;
  // Our u' from Bullet's accelerations `a` (solve()'s layout) at (q, u).  // udot: (nu)
  void ours(const double* q, const double* u, const double* a, double* udot) const;
  void poses(std::vector<Pose>& out) const;
  double kinetic() const;
  // Gravity's potential at Bullet's state and the springs' at q, ours (the same state).  // q: (nq)
  double potential(const double* q) const;

 private:
  // A closure's end in Bullet: the multibody (nullptr: the world, for a floating
  // tree's ground), its link (-1: the base) and our frame -> Bullet's (P^T).
  struct End {
    btMultiBody* mb = nullptr;
    int link = -1;
    Mat3 Pt = Mat3::Identity();
  };
  End end(int body) const;
  Mat3 linkFrame(const End& e) const;  // Bullet's link frame in the world, now
  void addLinks(const Body& b, const BulletLink& me);
  void setBase(const Body& b, const BulletLink& me, const double* q, const double* u);
  void getBase(const Body& b, const BulletLink& me, double* q, double* u) const;

  const Model& m_;
  bool floating_ = false;
  std::unique_ptr<btMultiBody> mb_;
  std::vector<BulletLink> links_;                 // internal order
  Eigen::VectorXd last_q_;                        // (nq): the last read-back, for angle branches
  btAlignedObjectArray<btScalar> scratch_r_;      // Bullet's forward-dynamics scratch
  btAlignedObjectArray<btVector3> scratch_v_;
  btAlignedObjectArray<btMatrix3x3> scratch_m_;
  mutable btAlignedObjectArray<btVector3> w_, v_; // (links + 1): link velocities, local frames
  mutable Workspace ws_;                          // the read-back state's kinematics: point springs' lines, potential
  Eigen::VectorXd zero_u_;                        // (nu): speeds where only positions matter
};

// Body i's place in Bullet: a free root alone is the floating base; else its
// one-speed links and its spherical one.
BulletLink bulletLink(const Body& b, bool base) {
  BulletLink l;
  l.frame = principal(b.J);
  l.joint = bulletJoint(b.joint);
  if (base) return l;
  l.scalars = static_cast<int>(l.joint.scalars.size());
  l.spherical = l.joint.spherical;
  return l;
}

BulletChain::BulletChain(const Model& m) : m_(m), links_(m.n()), last_q_(m.q0()), ws_(m), zero_u_(Eigen::VectorXd::Zero(m.nu)) {
  int roots = 0, nlinks = 0;
  for (const Body& b : m.bodies) roots += b.parent < 0;
  floating_ = roots == 1 && bulletJoint(m.bodies[0].joint).floats;
  for (int i = 0; i < m.n(); ++i) {
    BulletLink& l = links_[i];
    l = bulletLink(m.bodies[i], floating_ && i == 0);
    if (l.scalars + l.spherical == 0) continue;
    l.first = nlinks;
    nlinks += l.scalars + l.spherical;
    l.link = nlinks - 1;
  }
  const double base_mass = floating_ ? m.bodies[0].mass : 1.0;  // a fixed base's are never read
  const Vec3 base_I = floating_ ? links_[0].frame.I : Vec3::Ones();
  mb_ = std::make_unique<btMultiBody>(nlinks, base_mass, bt(base_I), !floating_, false);
  mb_->setLinearDamping(0);
  mb_->setAngularDamping(0);
  mb_->setMaxCoordinateVelocity(HUGE_VAL);
  mb_->setHasSelfCollision(false);
  for (int i = 0; i < m.n(); ++i)
    if (links_[i].link >= 0) addLinks(m.bodies[i], links_[i]);
  mb_->finalizeMultiDof();
  for (BulletLink& l : links_)
    if (l.link >= 0) l.dof = 6 + mb_->getLink(l.first).m_dofOffset;
  setState(m.q0().data(), m.u0().data());
}

// Body b's links: one-speed links massless at the joint point, parallel to
// the parent's frame (ours), then its own.
void BulletChain::addLinks(const Body& b, const BulletLink& me) {
  const Joint& j = b.joint;
  const Mat3& P = me.frame.P;
  const Mat3 Pp = b.parent < 0 ? Mat3::Identity() : links_[b.parent].frame.P;
  const btVector3 I = bt(me.frame.I), zero(0, 0, 0), d = bt(-(P.transpose() * j.in_body));
  int parent = b.parent < 0 ? -1 : links_[b.parent].link;
  btVector3 e = bt(Pp.transpose() * j.in_parent);
  btQuaternion rot = btQuat(Pp);  // the parent's frame -> a link parallel to ours, at q = 0
  auto own = [&](int k) { return k == me.link - me.first; };
  for (int k = 0; k < me.scalars; ++k) {
    const int l = me.first + k;
    const Vec3& axis = me.joint.scalars[k].axis;
    const bool mine = own(k);
    const btQuaternion r = mine ? btQuat(P.transpose()) * rot : rot;
    const btVector3 a = bt(mine ? P.transpose() * axis : axis);
    if (me.joint.scalars[k].slides)
      mb_->setupPrismatic(l, mine ? b.mass : 0, mine ? I : zero, parent, r, a, e, mine ? d : zero, true);
    else
      mb_->setupRevolute(l, mine ? b.mass : 0, mine ? I : zero, parent, r, a, e, mine ? d : zero, true);
    parent = l, e = zero, rot = btQuaternion::getIdentity();
  }
  if (me.spherical) mb_->setupSpherical(me.link, b.mass, I, parent, btQuat(P.transpose()) * rot, e, d, true);
}

void BulletChain::setBase(const Body& b, const BulletLink& me, const double* q, const double* u) {
  const Mat3 R = relativeRotation(b.joint, q);
  const Vec3 Rc = R * b.joint.in_body, v(u), w(u + 3);
  mb_->setBasePos(bt(b.joint.in_parent + slideOffset(b.joint, q) - Rc));
  mb_->setWorldToBaseRot(btQuat((R * me.frame.P).transpose()));
  mb_->setBaseVel(bt(v + Rc.cross(w)));
  mb_->setBaseOmega(bt(w));
}

void BulletChain::setState(const double* q, const double* u) {
  for (int i = 0; i < m_.n(); ++i) {
    const Body& b = m_.bodies[i];
    const BulletLink& l = links_[i];
    const double *qi = q + b.iq, *ui = u + b.iu;
    if (l.link < 0) {
      setBase(b, l, qi, ui);
      continue;
    }
    for (int k = 0; k < l.scalars; ++k) {
      mb_->setJointPos(l.first + k, qi[k]);
      mb_->setJointVel(l.first + k, ui[k]);
    }
    if (!l.spherical) continue;
    const Mat3& P = l.frame.P;
    const Vec4 r = matrixToQuat(P.transpose() * relativeRotation(b.joint, qi) * P);
    const double pos[4] = {r[1], r[2], r[3], r[0]};
    mb_->setJointPosMultiDof(l.link, pos);
    Mat3 G;
    Vec3 g;
    sphericalMap(b.joint, l.joint.angle_rates, P, qi, ui + l.scalars, G, g);
    const Vec3 w = G * Vec3(ui + l.scalars);
    mb_->setJointVelMultiDof(l.link, w.data());
  }
}

void BulletChain::getBase(const Body& b, const BulletLink& me, double* q, double* u) const {
  const Mat3 R = ev(mb_->getWorldToBaseRot()).transpose() * me.frame.P.transpose();
  const Vec3 Rc = R * b.joint.in_body, w = ev(mb_->getBaseOmega());
  jointCoordinates(b.joint, R, ev(mb_->getBasePos()) + Rc - b.joint.in_parent, last_q_.data() + b.iq, q);
  Eigen::Map<Vec3>{u} = ev(mb_->getBaseVel()) - Rc.cross(w);
  Eigen::Map<Vec3>{u + 3} = w;
}

void BulletChain::getState(Eigen::VectorXd& q, Eigen::VectorXd& u) {
  for (int i = 0; i < m_.n(); ++i) {
    const Body& b = m_.bodies[i];
    const BulletLink& l = links_[i];
    double *qi = q.data() + b.iq, *ui = u.data() + b.iu;
    if (l.link < 0) {
      getBase(b, l, qi, ui);
      continue;
    }
    for (int k = 0; k < l.scalars; ++k) {
      qi[k] = mb_->getJointPos(l.first + k);
      ui[k] = mb_->getJointVel(l.first + k);
    }
    if (!l.spherical) continue;
    const double* p = mb_->getJointPosMultiDof(l.link);
    const Mat3 R = l.frame.P * quatToMatrix(Vec4(p[3], p[0], p[1], p[2])) * l.frame.P.transpose();
    jointCoordinates(b.joint, R, slideOffset(b.joint, qi), last_q_.data() + b.iq, qi);  // a free joint's slide as read
    Mat3 G;
    Vec3 g;
    sphericalMap(b.joint, l.joint.angle_rates, l.frame.P, qi, ui + l.scalars, G, g);  // G depends on q alone
    Eigen::Map<Vec3>{ui + l.scalars} = G.partialPivLu().solve(Vec3(mb_->getJointVelMultiDof(l.link)));
  }
  last_q_ = q;
}

void BulletChain::addGravity() {
  const btVector3 g = bt(m_.gravity);
  if (floating_) mb_->addBaseForce(g * mb_->getBaseMass());
  for (int l = 0; l < mb_->getNumLinks(); ++l) mb_->addLinkForce(l, g * mb_->getLinkMass(l));
}

void BulletChain::addJointTorques(const double* q, const double* u, const Eigen::VectorXd& control) {
  for (int i = 0; i < m_.n(); ++i) {
    const Body& b = m_.bodies[i];
    const bool driven = b.joint.torque.size() > 0, controlled = b.joint.control.has_value() && control.size();
    if (!b.joint.has_spring && !driven && !controlled) continue;  // ball and free joints carry no spring nor control (io/scene_json.cpp)
    const BulletLink& l = links_[i];
    const double *qi = q + b.iq, *ui = u + b.iu;
    Eigen::Matrix<double, 6, 1> Q = Eigen::Matrix<double, 6, 1>::Zero();  // per speed of ours
    if (b.joint.has_spring)
      for (int k = 0; k < b.nu(); ++k) Q[k] = -b.joint.spring.k[k] * (qi[k] - b.joint.spring.q_rest[k]) - b.joint.spring.c[k] * ui[k];
    if (driven) Q.head(b.nu()) += b.joint.torque;
    if (controlled) Q.head(b.nu()) += control.segment(b.iu, b.nu());
    if (l.link < 0) {  // the floating base, [v, w] ours: Q = G^T [tau, F] for [w, v_CM] = [w, v + (R c) x w]
      const Vec3 Rc = relativeRotation(b.joint, qi) * b.joint.in_body, F = Q.head<3>();
      mb_->addBaseForce(bt(F));
      mb_->addBaseTorque(bt(Vec3(Q.segment<3>(3)) + Rc.cross(F)));
      continue;
    }
    for (int k = 0; k < l.scalars; ++k) mb_->addJointTorque(l.first + k, Q[k]);
    if (l.spherical) {  // ball and gimbal: Q = G^T tau
      Mat3 G;
      Vec3 g;
      sphericalMap(b.joint, l.joint.angle_rates, l.frame.P, qi, ui + l.scalars, G, g);
      const Vec3 tau = G.transpose().partialPivLu().solve(Vec3(Q.segment<3>(l.scalars)));
      mb_->addJointTorqueMultiDof(l.link, tau.data());
    }
  }
}

void BulletChain::addPointSpringForces(const double* q, const double* u) {
  if (m_.point_springs.empty()) return;
  formKinematics(m_, q, u, ws_);
  for (const PointSpring& s : m_.point_springs) {
    const PointMotion a = pointMotion(ws_, s.a), b = pointMotion(ws_, s.b);
    const Vec3 f = pointSpringForce(s, a.x, a.v, b.x, b.v);  // on a; -f on b
    for (const auto& [body, x, force] : {std::tuple<int, Vec3, Vec3>{s.a.body, a.x, f}, {s.b.body, b.x, -f}}) {
      if (body < 0) continue;
      const int link = links_[body].link;
      const Vec3 cm = ev(link < 0 ? mb_->getBasePos() : mb_->localPosToWorld(link, btVector3(0, 0, 0)));
      const Vec3 torque = (x - cm).cross(force);
      if (link < 0) mb_->addBaseForce(bt(force)), mb_->addBaseTorque(bt(torque));
      else mb_->addLinkForce(link, bt(force)), mb_->addLinkTorque(link, bt(torque));
    }
  }
}

BulletChain::End BulletChain::end(int body) const {
  if (body < 0) return {floating_ ? nullptr : mb_.get(), -1, Mat3::Identity()};  // the fixed base is the world's origin
  return {mb_.get(), links_[body].link, links_[body].frame.P.transpose()};
}

Mat3 BulletChain::linkFrame(const End& e) const {
  if (!e.mb) return Mat3::Identity();
  if (e.link < 0) return ev(mb_->getWorldToBaseRot()).transpose();
  const btMatrix3x3 B = mb_->localFrameToWorld(e.link, btMatrix3x3::getIdentity());
  Mat3 R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = B[r][c];
  return R;
}

std::vector<std::unique_ptr<btMultiBodyConstraint>> BulletChain::stops() {
  std::vector<std::unique_ptr<btMultiBodyConstraint>> out;
  for (int i = 0; i < m_.n(); ++i)
    if (const auto& l = m_.bodies[i].joint.limits)
      out.push_back(std::make_unique<btMultiBodyJointLimitConstraint>(mb_.get(), links_[i].link, l->lower[0], l->upper[0]));
  return out;
}

std::vector<std::unique_ptr<btMultiBodyConstraint>> BulletChain::closures() {
  constexpr double kLever = 1.0;  // m: a hinge's second pair of points, along the axes
  std::vector<std::unique_ptr<btMultiBodyConstraint>> out;
  for (const Loop& loop : m_.loops) {
    End a = end(loop.a.body), b = end(loop.b.body);
    const Vec3 line = (a.mb ? Mat3(linkFrame(a) * a.Pt) : Mat3::Identity()) * loop.axis_a;  // a slider's axis, world
    Vec3 xa = loop.a.point, xb = loop.b.point, da = loop.axis_a, db = loop.axis_b;
    if (!a.mb) std::swap(a, b), std::swap(xa, xb), std::swap(da, db);  // the world as Bullet's B side
    const auto pivot = [](const End& e, const Vec3& x) { return bt(e.Pt * x); };
    const auto connect = [&](const Vec3& pa, const Vec3& pb) {
      if (!b.mb) out.push_back(std::make_unique<btMultiBodyPoint2Point>(a.mb, a.link, nullptr, pivot(a, pa), bt(pb)));
      else out.push_back(std::make_unique<btMultiBodyPoint2Point>(a.mb, a.link, b.mb, b.link, pivot(a, pa), pivot(b, pb)));
    };
    const auto relativeFrame = [&] {  // b's link frame in a's, as it is now (assembled: rel)
      const Mat3 rel = linkFrame(a).transpose() * linkFrame(b);
      return btMatrix3x3(rel(0, 0), rel(0, 1), rel(0, 2), rel(1, 0), rel(1, 1), rel(1, 2), rel(2, 0), rel(2, 1), rel(2, 2));
    };
    switch (loop.type) {
      case LoopType::Ball: connect(xa, xb); break;
      case LoopType::Hinge:
        connect(xa, xb);
        connect(xa + kLever * da, xb + kLever * db);
        break;
      case LoopType::Weld: {  // the link frames' relative rotation as it is now (assembled: rel)
        const btMatrix3x3 frame_a = relativeFrame(), identity = btMatrix3x3::getIdentity();
        if (!b.mb)
          out.push_back(std::make_unique<btMultiBodyFixedConstraint>(a.mb, a.link, nullptr, pivot(a, xa), bt(xb), frame_a, identity));
        else
          out.push_back(std::make_unique<btMultiBodyFixedConstraint>(a.mb, a.link, b.mb, b.link, pivot(a, xa), pivot(b, xb),
                                                                     frame_a, identity));
        break;
      }
      case LoopType::Slider: {  // the pivots on one line along axis_a (in A's link frame), the frames' turn as it is now
        const btMatrix3x3 frame_a = relativeFrame(), identity = btMatrix3x3::getIdentity();
        const btVector3 axis = bt(Vec3(linkFrame(a).transpose() * line));
        if (!b.mb)
          out.push_back(std::make_unique<btMultiBodySliderConstraint>(a.mb, a.link, nullptr, pivot(a, xa), bt(xb), frame_a, identity, axis));
        else
          out.push_back(std::make_unique<btMultiBodySliderConstraint>(a.mb, a.link, b.mb, b.link, pivot(a, xa), pivot(b, xb), frame_a,
                                                                      identity, axis));
        break;
      }
      case LoopType::Universal:
        throw std::invalid_argument(unmappedLoop(m_, kBulletLoops, kBulletConstraints));
    }
  }
  return out;
}

const double* BulletChain::solve() {
  mb_->computeAccelerationsArticulatedBodyAlgorithmMultiDof(0, scratch_r_, scratch_v_, scratch_m_, false, false, false);
  mb_->clearForcesAndTorques();
  return &scratch_r_[mb_->getNumDofs()];  // Bullet's layout: [w', v'_CM] of the base, then the links' (dt 0: speeds kept)
}

void BulletChain::forwardDynamics(const double* q, const double* u, double* udot) {
  mb_->clearForcesAndTorques();
  addGravity();
  addJointTorques(q, u);
  addPointSpringForces(q, u);
  ours(q, u, solve(), udot);
}

void BulletChain::ours(const double* q, const double* u, const double* a, double* udot) const {
  for (int i = 0; i < m_.n(); ++i) {
    const Body& b = m_.bodies[i];
    const BulletLink& l = links_[i];
    const double *qi = q + b.iq, *ui = u + b.iu;
    double* ud = udot + b.iu;
    if (l.link < 0) {  // the base: v' = v'_CM - (R c) x w' - (w x R c) x w
      const Vec3 Rc = relativeRotation(b.joint, qi) * b.joint.in_body, w(ui + 3), wdot(a);
      Eigen::Map<Vec3>{ud} = Vec3(a + 3) - Rc.cross(wdot) - w.cross(Rc).cross(w);
      Eigen::Map<Vec3>{ud + 3} = wdot;
      continue;
    }
    for (int k = 0; k < l.scalars; ++k) ud[k] = a[l.dof + k];
    if (!l.spherical) continue;
    Mat3 G;
    Vec3 g;
    sphericalMap(b.joint, l.joint.angle_rates, l.frame.P, qi, ui + l.scalars, G, g);
    Eigen::Map<Vec3>{ud + l.scalars} = G.partialPivLu().solve(Vec3(a + l.dof + l.scalars) - g);
  }
}

Eigen::MatrixXd BulletChain::massMatrix(const double* q, const double* u) {
  const int n = speeds(), first = firstSpeed();
  Eigen::MatrixXd Minv(n, n);
  mb_->clearVelocities();
  for (int k = 0; k < n; ++k) {
    mb_->clearForcesAndTorques();
    const int s = first + k;  // a unit generalized force on Bullet's speed s
    if (s < 3) {
      btVector3 t(0, 0, 0);
      t[s] = 1;
      mb_->addBaseTorque(t);
    } else if (s < 6) {
      btVector3 f(0, 0, 0);
      f[s - 3] = 1;
      mb_->addBaseForce(f);
    } else {
      for (int l = 0; l < mb_->getNumLinks(); ++l) {
        const btMultibodyLink& link = mb_->getLink(l);
        if (s - 6 >= link.m_dofOffset && s - 6 < link.m_dofOffset + link.m_dofCount)
          mb_->addJointTorqueMultiDof(l, s - 6 - link.m_dofOffset, 1);
      }
    }
    Minv.col(k) = Eigen::Map<const Eigen::VectorXd>(solve() + first, n);
  }
  setState(q, u);
  return Minv.inverse();
}

void BulletChain::speedMap(const double* q, const double* u, Eigen::MatrixXd& G) const {
  const int first = firstSpeed();
  G.setZero(speeds(), m_.nu);
  for (int i = 0; i < m_.n(); ++i) {
    const Body& b = m_.bodies[i];
    const BulletLink& l = links_[i];
    const int r = l.dof - first;
    const double *qi = q + b.iq, *ui = u + b.iu;
    if (l.link < 0) {  // [w, v_CM] = [w, v + (R c) x w]
      const Vec3 Rc = relativeRotation(b.joint, qi) * b.joint.in_body;
      G.block<3, 3>(r, b.iu + 3) = Mat3::Identity();
      G.block<3, 3>(r + 3, b.iu) = Mat3::Identity();
      G.block<3, 3>(r + 3, b.iu + 3) = skew(Rc);
      continue;
    }
    for (int k = 0; k < l.scalars; ++k) G(r + k, b.iu + k) = 1;
    if (!l.spherical) continue;
    Mat3 Gi;
    Vec3 gi;  // its rate term: unused here
    sphericalMap(b.joint, l.joint.angle_rates, l.frame.P, qi, ui + l.scalars, Gi, gi);
    G.block<3, 3>(r + l.scalars, b.iu + l.scalars) = Gi;
  }
}

void BulletChain::poses(std::vector<Pose>& out) const {
  out.resize(m_.n());
  for (int i = 0; i < m_.n(); ++i) {
    const BulletLink& l = links_[i];
    if (l.link < 0) {
      out[i] = {ev(mb_->getBasePos()), matrixToQuat(ev(mb_->getWorldToBaseRot()).transpose() * l.frame.P.transpose())};
      continue;
    }
    const btMatrix3x3 B = mb_->localFrameToWorld(l.link, btMatrix3x3::getIdentity());
    Mat3 R;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R(r, c) = B[r][c];
    out[i] = {ev(mb_->localPosToWorld(l.link, btVector3(0, 0, 0))), matrixToQuat(R * l.frame.P.transpose())};
  }
}

double BulletChain::kinetic() const {
  const int n = mb_->getNumLinks();
  w_.resize(n + 1);
  v_.resize(n + 1);
  mb_->compTreeLinkVelocities(&w_[0], &v_[0]);
  double T = 0;
  if (floating_) T += 0.5 * (mb_->getBaseMass() * v_[0].length2() + w_[0].dot(mb_->getBaseInertia() * w_[0]));
  for (int l = 0; l < n; ++l)
    T += 0.5 * (mb_->getLinkMass(l) * v_[l + 1].length2() + w_[l + 1].dot(mb_->getLinkInertia(l) * w_[l + 1]));
  return T;
}

double BulletChain::potential(const double* q) const {
  const Vec3& g = m_.gravity;
  double V = floating_ ? -mb_->getBaseMass() * g.dot(ev(mb_->getBasePos())) : 0;
  for (int l = 0; l < mb_->getNumLinks(); ++l)
    V -= mb_->getLinkMass(l) * g.dot(ev(mb_->localPosToWorld(l, btVector3(0, 0, 0))));
  for (const Body& b : m_.bodies)  // the springs' own: Bullet has none
    if (b.joint.has_spring)
      for (int k = 0; k < b.nu(); ++k) {
        const double x = q[b.iq + k] - b.joint.spring.q_rest[k];
        V += 0.5 * b.joint.spring.k[k] * x * x;
      }
  if (!m_.point_springs.empty()) {
    formKinematics(m_, q, zero_u_.data(), ws_);  // positions alone matter
    V += pointSpringPotential(m_, ws_);
  }
  return V;
}

// Bullet's equations at any state: its forward dynamics, and the mass matrix
// and right-hand side it implies (Bullet exposes no other).
class BulletModel : public EngineModel {
 public:
  explicit BulletModel(const Model& m) : m_(m), chain_(m) {}
  EngineEquations at(const Eigen::VectorXd& q, const Eigen::VectorXd& u) override {
    EngineEquations e;
    chain_.setState(q.data(), u.data());
    e.udot.resize(m_.nu);
    chain_.forwardDynamics(q.data(), u.data(), e.udot.data());
    e.kinetic = chain_.kinetic();
    e.potential = chain_.potential(q.data());
    const Eigen::MatrixXd M = chain_.massMatrix(q.data(), u.data());
    Eigen::MatrixXd G;
    chain_.speedMap(q.data(), u.data(), G);
    e.A = G.transpose() * M * G;
    e.B = e.A * e.udot;
    return e;
  }

 private:
  const Model& m_;
  BulletChain chain_;
};

// What of Bullet's crosscheck entries is eigenmass's: B is always A u' (A
// from its u'), and a ball, gimbal or free joint's speeds reach ours through
// sphericalMap and the floating base's lever, i.e. eigenmass's own joint
// kinematics (relativeRotation, worldAxes, axisRates): a bug there is Bullet's too.
EquationsDependence bulletDependence(const Model& m) {
  EquationsDependence d;
  d.B = "B is A u' (Bullet exposes no right-hand side)";
  if (const std::string j = jointsOfKinds(m, {JointType::Ball, JointType::Gimbal, JointType::Free}); !j.empty())
    d.A = d.udot = "the speeds of its joints of kind " + j + " map to ours through eigenmass's joint kinematics (solver/joints/)";
  return d;
}

// btMultiBodyDynamicsWorld with its multibody constraints solved as one
// group. Bullet 3.24 reaches them only through colliders' simulation islands:
// with none (eigenmass adds no colliders) no island is processed, and its
// island-less branch passes the count of typed constraints, 0, as theirs
// (MultiBodyInplaceSolverIslandCallback::processIsland). So the group is
// handed to the same solver directly, between the same two stages.
class ClosedLoopWorld : public btMultiBodyDynamicsWorld {
 public:
  using btMultiBodyDynamicsWorld::btMultiBodyDynamicsWorld;
  void solveConstraints(btContactSolverInfo& info) override {
    solveExternalForces(info);
    if (const int n = m_multiBodyConstraints.size())
      m_multiBodyConstraintSolver->solveMultiBodyGroup(nullptr, 0, nullptr, 0, nullptr, 0, &m_multiBodyConstraints[0], n, info,
                                                       m_debugDrawer, m_dispatcher1);
    solveInternalConstraints(info);
  }
};

// Bullet's schemes: their ids, the order of its row's schemes (bulletEngine).
enum BulletScheme { kBulletEuler, kBulletRk4, kBulletSchemes };

// btMultiBodyDynamicsWorld::stepSimulation at exactly dt (no sub-steps), no
// colliders: Bullet's semi-implicit Euler, or btMultiBody's rk4 (four
// forward dynamics per step), the springs' torques held over the step.
class BulletStepper : public FixedStepEngine {
 public:
  BulletStepper(const Model& m, const RunSpec& spec)
      : m_(m), chain_(m), dt_(spec.dt), q_(m.q0()), u_(m.u0()), udot_(m.nu), forces_(false) {
    forces_ = m.hasAppliedForces();
    rk4_ = schemeIndex(spec.engine(), spec.integrator) == kBulletRk4;
    chain_.body().useRK4Integration(rk4_);
    world_.setGravity(bt(m.gravity));
    world_.addMultiBody(&chain_.body());
    closures_ = chain_.closures();
    for (auto& c : chain_.stops()) closures_.push_back(std::move(c));  // the joint limits: constraints of the same solver
    for (auto& c : closures_) world_.addMultiBodyConstraint(c.get());
    if (!closures_.empty()) {
      const MethodInfo& row = info(spec.method);
      world_.getSolverInfo().m_erp = row.param("bullet_erp", spec.options);
      world_.getSolverInfo().m_numIterations = static_cast<int>(row.param("bullet_iterations", spec.options));
    }

  }
  ~BulletStepper() override {
    for (auto& c : closures_) world_.removeMultiBodyConstraint(c.get());
    world_.removeMultiBody(&chain_.body());
  }
  std::string step() override {
    if (forces_) {
      chain_.getState(q_, u_);
      chain_.addJointTorques(q_.data(), u_.data(), control_);
      chain_.addPointSpringForces(q_.data(), u_.data());
    }
    world_.stepSimulation(dt_, 0, dt_);
    evaluations_ += rk4_ ? 5 : 1;  // rk4: four stages and a fifth at the start state (btMultiBodyDynamicsWorld)
    return "";
  }
  long evaluations() const override { return evaluations_; }
  void applyControl(const Eigen::VectorXd& tau) override { control_ = tau; }
  void state(Eigen::VectorXd& q, Eigen::VectorXd& u) override { chain_.getState(q, u); }
  void sample(std::vector<Pose>& poses, double& kinetic, double& potential) override {
    chain_.getState(q_, u_);
    chain_.poses(poses);
    kinetic = chain_.kinetic();
    potential = chain_.potential(q_.data());
  }
  void dissipation(double& P, double& Pdot) override {
    chain_.getState(q_, u_);
    if (m_.isMechanism()) {  // P by theory.md eq. (M6); the tree's u' is not the mechanism's, so P' = 0 (the plain trapezoid rule)
      formKinematics(m_, q_.data(), u_.data(), ws_);
      P = nonConservativePower(m_, ws_, u_.data());
      Pdot = 0;
      return;
    }
    chain_.forwardDynamics(q_.data(), u_.data(), udot_.data());
    P = Pdot = 0;
    for (const Body& b : m_.bodies) {
      if (!b.joint.has_spring) continue;
      for (int k = 0; k < b.nu(); ++k) {
        const double c = b.joint.spring.c[k], v = u_[b.iu + k];
        P += c * v * v;
        Pdot += 2 * c * v * udot_[b.iu + k];
      }
    }
  }

 private:
  const Model& m_;
  BulletChain chain_;
  double dt_;
  Eigen::VectorXd q_, u_, udot_;  // (nq), (nu), (nu): the state the springs act at
  Workspace ws_{m_};              // a mechanism's read-back kinematics, for its power
  Eigen::VectorXd control_;       // a joint controller's held torques (nu), empty before the first
  bool forces_, rk4_ = false;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> closures_;  // removed from the world before it goes
  long evaluations_ = 0;
  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_{&config_};
  btDbvtBroadphase broadphase_;
  btMultiBodyConstraintSolver solver_;
  ClosedLoopWorld world_{&dispatcher_, &broadphase_, &solver_, &config_};
};

// bullet-udot: Bullet's u' (its forward dynamics) under the in-house integrators.
class BulletUdot final : public MethodImpl {
 public:
  explicit BulletUdot(const Model& m) : chain_(m) {}
  bool needsEquations() const override { return false; }
  bool needsKinematics() const override { return false; }
  Status rates(double, const double* q, const double* u, const Workspace&, const double*, double* udot, double*,
               EvalInfo&) override {
    chain_.setState(q, u);
    chain_.forwardDynamics(q, u, udot);
    return {};
  }

 private:
  BulletChain chain_;
};

std::unique_ptr<MethodImpl> makeBulletUdot(const Model& m, const MethodInfo&, const MethodOptions&) {
  return std::make_unique<BulletUdot>(m);
}

}  // namespace


// What Bullet does to this scene that bounds its agreement: its slider rows
// (btMultiBodySliderConstraint::createConstraintRows) take the line's body's
// velocity at the line's pivot, not at the slider's point, so on a line that
// turns they are not the derivative of the slider's gap. Its runs then close
// the loop but converge to another motion (docs/reference-engines.md).
std::string bulletSceneNote(const Model& m) {
  if (!m.limited.empty())
    return "joint limits: Bullet's btMultiBodyJointLimitConstraint (an inelastic stop: no restitution, e is not mapped; "
           "its solver's ERP and iterations as for closures)";
  for (const Loop& l : m.loops)
    if (l.type == LoopType::Slider && l.a.body >= 0 && l.b.body >= 0)
      return "loop '" + l.name + "': Bullet's slider constraint takes the turning line's velocity at its pivot, not at the "
             "slider's point (btMultiBodySliderConstraint): its runs converge to another motion where the line turns";
  return "";
}

EngineRow bulletEngine() {
  EngineRow r;
  r.info.name = "bullet";
  r.info.summary = "Bullet 3.24's btMultiBody stepped by btMultiBodyDynamicsWorld (Featherstone's articulated bodies, "
                   "semi-implicit Euler or its rk4, springs and dampers as joint torques held over a step), fixed step "
                   "(what PyBullet runs)";
  r.info.schemes.resize(kBulletSchemes);  // each at its id
  r.info.schemes[kBulletEuler] = {"bullet-euler", true, "Bullet's semi-implicit Euler (stepSimulation: velocities, then positions from them)", "P"};
  r.info.schemes[kBulletRk4] = {"bullet-rk4", true, "btMultiBody's own rk4 (useRK4Integration; the springs' torques held over the step)", "X"};
  r.info.fixed_scheme = "bullet-euler";
  r.info.adaptive_scheme = "bullet-euler";  // Bullet has no adaptive scheme
  r.info.colour = "darkgoldenrod";
  // Its closures' stabilization: btContactSolverInfo's defaults, read only where loops are.
  r.info.params = {
      {"bullet_erp", 0.2, 0, 1, false, "Bullet: its closures' error reduction parameter, the share of a loop's violation fed back per step (its default 0.2)", nullptr, true},
      {"bullet_iterations", 10, 1, 10000, true, "Bullet: its constraint solver's sequential-impulse iterations per step (its default 10)", nullptr, true}};
  r.code.simulate = simulateFixedStep<BulletStepper>;
  r.code.model = [](const Model& m) -> std::unique_ptr<EngineModel> { return std::make_unique<BulletModel>(m); };
  // no urdf: Bullet's URDF importer is not in libbullet-dev
  r.code.version = [] { return std::to_string(BT_BULLET_VERSION / 100) + "." + std::to_string(BT_BULLET_VERSION % 100); };
  r.code.udot_method = {"bullet-udot", "Bullet's u' (its articulated-body forward dynamics) under the in-house integrators: "
                                       "Bullet's formulation apart from its integrator", "#5c4000", makeBulletUdot};
  r.code.mechanism_refusal = [](const Model& m) { return unmappedLoop(m, kBulletLoops, kBulletConstraints); };  // point springs and drives all map
  r.code.mechanism_state = "Bullet's forward dynamics at a state is its multibody's, a mechanism's tree: its constraints act "
                           "only inside its solver's step, and point springs and drives are applied there; its A is judged, "
                           "its B and u' of a mechanism are not exposed";
  r.code.dependence = bulletDependence;
  r.code.scene_note = bulletSceneNote;
  r.code.limits_refusal = [](const Model& m) -> std::string {
    for (const Body& b : m.bodies)
      if (b.joint.limits && b.joint.type != JointType::Revolute && b.joint.type != JointType::Prismatic)
        return std::string("the limits of body '") + b.name + "': Bullet's btMultiBodyJointLimitConstraint holds one-speed links, not a " +
               jointTypeName(b.joint.type) + " joint";
    return "";
  };
  r.code.equations_note = "Bullet exposes no mass matrix: A is the inverse of its forward dynamics under unit forces at rest "
                          "without gravity, B = A u'; both err by ~eps cond(A), as u' does";
  return r;
}

}  // namespace em
