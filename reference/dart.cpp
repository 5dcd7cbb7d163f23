// DART 6.12 (libdart-dev) as an engine, row `dart` (docs/engines.md):
//
// The Model as a DART Skeleton, built in code: one BodyNode per body, its
// frame at the CM and parallel to ours (local COM 0, the full inertia
// tensor), the joint at the joint point on both sides (T_ParentBodyToJoint =
// translation a, T_ChildBodyToJoint = translation c). Every joint kind maps
// exactly: revolute, prismatic, universal and planar to DART's (PlanarJoint
// on the arbitrary plane of e1, e2: the same coordinates), the gimbal to
// EulerJoint XYZ (Rx Ry Rz, as ours), ball to BallJoint and free to
// FreeJoint; springs and dampers to the joints' stiffness, rest position and
// damping. Coordinates are ours except where DART's differ:
//   ball: DART's positions are the rotation vector log(R), its speeds the
//         angular velocity in the child frame, R^T w;
//   free: positions [log(R), x], speeds [R^T w, R^T v] (angular first);
//         their rate has the bias -R^T (w x v) in the linear part.
// So u_D = G u with G orthogonal per joint, A = G^T M_D G,
// B = G^T (B_D - M_D g), u' = G^T (u'_D - g), g = G' u.
//
// Mechanisms (docs/reference-engines.md, "Mechanisms"): DART's constraint
// solver closes the loops, made at the assembled initial state: a ball closure
// a BallJointConstraint at the point, a hinge two (the points, and the points
// 1 m along the axes), a weld a WeldJointConstraint (the relative transform it
// finds); the ground is the world. They are impulses at the velocity level,
// the drift fed back at DART's DynamicJointConstraint defaults (ERP, its
// error allowance and CFM, read from DART and stated in every report). Drives
// are joint forces (u_D = G u, G orthogonal: DART's forces G tau), point
// springs external forces at their points, from DART's own poses and
// velocities, held over a step.
//
// Two ways to run it: `dart` is World::step, DART's semi-implicit Euler at a
// fixed dt with its own (implicit) springs and dampers: what a Gazebo user
// gets. `dart-udot` is DART's u' (its articulated-body forward dynamics) under
// the in-house integrators: DART's formulation apart from its integrator.
#include <dart/config.hpp>
#include <dart/constraint/BallJointConstraint.hpp>
#include <dart/constraint/ConstraintSolver.hpp>
#include <dart/constraint/WeldJointConstraint.hpp>
#include <dart/dynamics/BallJoint.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/EulerJoint.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/PlanarJoint.hpp>
#include <dart/dynamics/PrismaticJoint.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/UniversalJoint.hpp>
#include <dart/simulation/World.hpp>
#include <dart/utils/urdf/DartLoader.hpp>

#include <iostream>
#include <sstream>
#include <stdexcept>

#include "reference/engine.hpp"
#include "reference/fixed_step.hpp"
#include "reference/urdf_text.hpp"
#include "solver/formation.hpp"
#include "solver/applied_forces.hpp"
#include "solver/method.hpp"

namespace em {

// The closure kinds DART 6.12's joint constraints express (addClosure); the others are refused by name.
const std::vector<LoopType> kDartLoops = {LoopType::Ball, LoopType::Hinge, LoopType::Weld};
constexpr const char* kDartConstraints = "DART 6.12's joint constraints (BallJointConstraint, WeldJointConstraint)";

namespace {

namespace dd = dart::dynamics;

// DART's forward dynamics treats springs and dampers implicitly over the
// skeleton's time step (stiffness dt^2 and damping dt in the articulated
// inertia, the spring at q + dt u). At a state the step is set this small:
// the implicit share is then ~1e-15 relative (measured: 2e-14 on a damped
// pendulum at 16 m/s^2), and u' is the explicit one the other engines give.
constexpr double kStateTimeStep = 1e-15;

// Eigen objects are never passed by value out of libdart: a dynamic vector
// allocated there (its Eigen takes glibc's malloc as aligned) and freed here
// mismatches under ASan, where Eigen allocates with its own alignment header.
// DART's state is read one degree of freedom at a time, into our vectors.  // x: (dofs)
void readPositions(const dd::Skeleton& s, Eigen::VectorXd& x) {
  for (size_t k = 0; k < s.getNumDofs(); ++k) x[k] = s.getPosition(k);
}
void readVelocities(const dd::Skeleton& s, Eigen::VectorXd& x) {
  for (size_t k = 0; k < s.getNumDofs(); ++k) x[k] = s.getVelocity(k);
}
void readAccelerations(const dd::Skeleton& s, Eigen::VectorXd& x) {
  for (size_t k = 0; k < s.getNumDofs(); ++k) x[k] = s.getAcceleration(k);
}

// DART writes its warnings to std::cout and std::cerr: none may reach
// eigenmass's output. Both are held while DART works; what it said is kept.
class QuietDart {
 public:
  QuietDart() : out_(std::cout.rdbuf(said_.rdbuf())), err_(std::cerr.rdbuf(said_.rdbuf())) {}
  ~QuietDart() {
    std::cout.rdbuf(out_);
    std::cerr.rdbuf(err_);
  }
  std::string said() const { return said_.str(); }

 private:
  std::ostringstream said_;
  std::streambuf *out_, *err_;
};

template <class J>
typename J::Properties jointProperties(const Body& b) {
  typename J::Properties p;
  p.mName = b.name;
  p.mT_ParentBodyToJoint = Eigen::Isometry3d::Identity();
  p.mT_ParentBodyToJoint.translation() = b.joint.in_parent;
  p.mT_ChildBodyToJoint = Eigen::Isometry3d::Identity();
  p.mT_ChildBodyToJoint.translation() = b.joint.in_body;
  for (size_t k = 0; k < p.mDofNames.size(); ++k) {  // our coordinates' names: unique, and DART has nothing to rename
    p.mDofNames[k] = b.joint.prefix(b.name) + ".q" + std::to_string(k);
    p.mPreserveDofNames[k] = true;
  }
  if (const auto& l = b.joint.limits) {  // its JointLimitConstraint in World::step (docs/reference-engines.md, "Joint limits")
    p.mPositionLowerLimits = l->lower;
    p.mPositionUpperLimits = l->upper;
    p.mIsPositionLimitEnforced = true;
  }
  if (b.joint.has_spring) {  // ball and free joints carry none (io/scene_json.cpp)
    p.mSpringStiffnesses = b.joint.spring.k;
    p.mRestPositions = b.joint.spring.q_rest;
    p.mDampingCoefficients = b.joint.spring.c;
  }
  return p;
}

// How DART keeps a joint's coordinates and speeds: as ours; or as a ball's,
// the rotation vector log(R) and the angular velocity in the child frame
// R^T w; or as a free joint's, [log(R), x] and [R^T w, R^T v].
enum class DartCoordinates { Ours, Ball, Free };

template <class J>
dd::BodyNode* create(const dd::SkeletonPtr& skel, dd::BodyNode* parent, const typename J::Properties& p,
                     const dd::BodyNode::Properties& bp) {
  return skel->createJointAndBodyNodePair<J>(parent, p, bp).second;
}

// Body b on its joint in the skeleton, the one mapping of kinds: the DART
// joint each kind is, and how its coordinates read (`coordinates`).
dd::BodyNode* addBody(const dd::SkeletonPtr& skel, dd::BodyNode* parent, const Body& b, DartCoordinates& coordinates) {
  dd::BodyNode::Properties bp;
  bp.mName = b.name;
  bp.mInertia = dd::Inertia(b.mass, Vec3::Zero(), b.J);
  const Joint& j = b.joint;
  coordinates = DartCoordinates::Ours;
  switch (j.type) {
    case JointType::Revolute: {
      auto p = jointProperties<dd::RevoluteJoint>(b);
      p.mAxis = j.axis[0];
      return create<dd::RevoluteJoint>(skel, parent, p, bp);
    }
    case JointType::Prismatic: {
      auto p = jointProperties<dd::PrismaticJoint>(b);
      p.mAxis = j.axis[0];
      return create<dd::PrismaticJoint>(skel, parent, p, bp);
    }
    case JointType::Universal: {
      auto p = jointProperties<dd::UniversalJoint>(b);
      p.mAxis = {j.axis[0], j.axis[1]};
      return create<dd::UniversalJoint>(skel, parent, p, bp);
    }
    case JointType::Gimbal: {  // EulerJoint XYZ is Rx Ry Rz, as ours
      auto p = jointProperties<dd::EulerJoint>(b);
      p.mAxisOrder = dd::EulerJoint::AxisOrder::XYZ;
      return create<dd::EulerJoint>(skel, parent, p, bp);
    }
    case JointType::Planar: {  // translation q0 e1 + q1 e2, then the turn q2 about e1 x e2: ours
      auto p = jointProperties<dd::PlanarJoint>(b);
      p.setArbitraryPlane(j.axis[0], j.axis[1]);
      return create<dd::PlanarJoint>(skel, parent, p, bp);
    }
    case JointType::Ball:
      coordinates = DartCoordinates::Ball;
      return create<dd::BallJoint>(skel, parent, jointProperties<dd::BallJoint>(b), bp);
    case JointType::Free:
      coordinates = DartCoordinates::Free;
      return create<dd::FreeJoint>(skel, parent, jointProperties<dd::FreeJoint>(b), bp);
  }
  throw std::logic_error("DART: a joint kind without a mapping");
}

// The Model as a DART skeleton, and the map between our state and DART's.
class DartSkeleton {
 public:
  explicit DartSkeleton(const Model& m) : m_(m), skel_(dd::Skeleton::create(m.name)), dof_(m.n()), coordinates_(m.n()) {
    std::vector<dd::BodyNode*> node(m.n());
    for (int i = 0; i < m.n(); ++i) {  // parents first
      const Body& b = m.bodies[i];
      node[i] = addBody(skel_, b.parent < 0 ? nullptr : node[b.parent], b, coordinates_[i]);
      dof_[i] = static_cast<int>(node[i]->getParentJoint()->getIndexInSkeleton(0));
    }
    nodes_ = node;
    skel_->setGravity(m.gravity);
    pos_.resize(m.nu);
    vel_.resize(m.nu);
    accel_.resize(m.nu);
  }

  const dd::SkeletonPtr& skeleton() const { return skel_; }
  dd::BodyNode* node(int i) const { return nodes_[i]; }  // internal order

  // Our (q, u), internal order, into DART's positions and speeds.
  void setState(const double* q, const double* u) {
    for (int i = 0; i < m_.n(); ++i) {
      const Body& b = m_.bodies[i];
      const int d = dof_[i];
      const double *qi = q + b.iq, *ui = u + b.iu;
      switch (coordinates_[i]) {
        case DartCoordinates::Ball: {
          const Mat3 R = quatToMatrix(Vec4(qi[0], qi[1], qi[2], qi[3]).normalized());
          pos_.segment<3>(d) = dd::BallJoint::convertToPositions(R);
          vel_.segment<3>(d) = R.transpose() * Vec3(ui);
          break;
        }
        case DartCoordinates::Free: {
          const Mat3 R = quatToMatrix(Vec4(qi[3], qi[4], qi[5], qi[6]).normalized());
          pos_.segment<3>(d) = dd::BallJoint::convertToPositions(R);
          pos_.segment<3>(d + 3) = Vec3(qi);
          vel_.segment<3>(d) = R.transpose() * Vec3(ui + 3);
          vel_.segment<3>(d + 3) = R.transpose() * Vec3(ui);
          break;
        }
        case DartCoordinates::Ours:
          for (int k = 0; k < b.nq(); ++k) pos_[d + k] = qi[k];
          for (int k = 0; k < b.nu(); ++k) vel_[d + k] = ui[k];
      }
    }
    skel_->setPositions(pos_);
    skel_->setVelocities(vel_);
  }

  // DART's state as our (q, u), internal order.
  void getState(Eigen::VectorXd& q, Eigen::VectorXd& u) {
    readPositions(*skel_, pos_);
    readVelocities(*skel_, vel_);
    const Eigen::VectorXd &pos = pos_, &vel = vel_;
    for (int i = 0; i < m_.n(); ++i) {
      const Body& b = m_.bodies[i];
      const int d = dof_[i];
      switch (coordinates_[i]) {
        case DartCoordinates::Ball: {
          const Mat3 R = dd::BallJoint::convertToRotation(pos.segment<3>(d));
          q.segment<4>(b.iq) = matrixToQuat(R);
          u.segment<3>(b.iu) = R * vel.segment<3>(d);
          break;
        }
        case DartCoordinates::Free: {
          const Mat3 R = dd::BallJoint::convertToRotation(pos.segment<3>(d));
          q.segment<3>(b.iq) = pos.segment<3>(d + 3);
          q.segment<4>(b.iq + 3) = matrixToQuat(R);
          u.segment<3>(b.iu) = R * vel.segment<3>(d + 3);
          u.segment<3>(b.iu + 3) = R * vel.segment<3>(d);
          break;
        }
        case DartCoordinates::Ours:
          q.segment(b.iq, b.nq()) = pos.segment(d, b.nq());
          u.segment(b.iu, b.nu()) = vel.segment(d, b.nu());
      }
    }
  }

  // Our u' from DART's accelerations at the state last set (u: ours there).  // udot: (nu)
  void accelerations(const double* u, double* udot) {
    readAccelerations(*skel_, accel_);
    const Eigen::VectorXd& a = accel_;
    for (int i = 0; i < m_.n(); ++i) {
      const Body& b = m_.bodies[i];
      const int d = dof_[i];
      double* ud = udot + b.iu;
      switch (coordinates_[i]) {
        case DartCoordinates::Ball: Eigen::Map<Vec3>{ud} = rotation(i) * a.segment<3>(d); break;
        case DartCoordinates::Free: {
          const Mat3 R = rotation(i);
          const Vec3 w(u + b.iu + 3), v(u + b.iu);
          Eigen::Map<Vec3>{ud} = R * a.segment<3>(d + 3) + w.cross(v);  // u'_D = R^T (v' - w x v)
          Eigen::Map<Vec3>{ud + 3} = R * a.segment<3>(d);
          break;
        }
        case DartCoordinates::Ours:
          for (int k = 0; k < b.nu(); ++k) ud[k] = a[d + k];
      }
    }
  }

  // G (u_D = G u; DART's speed order by rows, ours by columns) and g = G' u at
  // the state last set (u: ours there).  // G: (nu x nu), g: (nu)
  void speedMap(const double* u, Eigen::MatrixXd& G, Eigen::VectorXd& g) const {
    G.setZero(m_.nu, m_.nu);
    g.setZero(m_.nu);
    for (int i = 0; i < m_.n(); ++i) {
      const Body& b = m_.bodies[i];
      const int d = dof_[i];
      switch (coordinates_[i]) {
        case DartCoordinates::Ball: G.block<3, 3>(d, b.iu) = rotation(i).transpose(); break;
        case DartCoordinates::Free: {
          const Mat3 Rt = rotation(i).transpose();
          G.block<3, 3>(d, b.iu + 3) = Rt;
          G.block<3, 3>(d + 3, b.iu) = Rt;
          g.segment<3>(d + 3) = -Rt * Vec3(u + b.iu + 3).cross(Vec3(u + b.iu));
          break;
        }
        case DartCoordinates::Ours:
          for (int k = 0; k < b.nu(); ++k) G(d + k, b.iu + k) = 1;
      }
    }
  }

  // Poses (CM position, orientation) of every body, internal order.
  void poses(std::vector<Pose>& out) const {
    out.resize(m_.n());
    for (int i = 0; i < m_.n(); ++i) {
      const Eigen::Isometry3d& T = nodes_[i]->getWorldTransform();
      out[i] = {T.translation(), matrixToQuat(T.linear())};
    }
  }

 private:
  // The joint's relative rotation R (ball, free) at the state last set.
  Mat3 rotation(int i) const { return nodes_[i]->getParentJoint()->getRelativeTransform().linear(); }

  const Model& m_;
  dd::SkeletonPtr skel_;
  std::vector<dd::BodyNode*> nodes_;  // internal order
  std::vector<int> dof_;              // DART index of body i's first speed
  std::vector<DartCoordinates> coordinates_;  // how DART keeps body i's joint coordinates
  Eigen::VectorXd pos_, vel_;         // (nu): DART's positions and speeds (nq_D = nu)
  Eigen::VectorXd accel_;             // (nu): DART's accelerations, read by accelerations()
};

// DART's equations at any state: its mass matrix, its C + g, its joint
// springs and dampers, and its forward dynamics.
class DartModel : public EngineModel {
 public:
  explicit DartModel(const Model& m) : m_(m), dart_(m) { dart_.skeleton()->setTimeStep(kStateTimeStep); }
  EngineEquations at(const Eigen::VectorXd& q, const Eigen::VectorXd& u) override {
    const dd::SkeletonPtr& s = dart_.skeleton();
    dart_.setState(q.data(), u.data());
    const Eigen::MatrixXd M = s->getMassMatrix();
    Eigen::VectorXd BD = -s->getCoriolisAndGravityForces();
    for (size_t k = 0; k < s->getNumDofs(); ++k) {  // its springs and dampers: -k (q - rest) - c u
      const dd::DegreeOfFreedom* f = s->getDof(k);
      BD[k] -= f->getSpringStiffness() * (f->getPosition() - f->getRestPosition()) + f->getDampingCoefficient() * f->getVelocity();
    }
    s->computeForwardDynamics();
    EngineEquations e;
    Eigen::MatrixXd G;
    Eigen::VectorXd g;
    dart_.speedMap(u.data(), G, g);
    e.A = G.transpose() * M * G;
    e.B = G.transpose() * (BD - M * g);
    e.udot.resize(m_.nu);
    dart_.accelerations(u.data(), e.udot.data());
    e.kinetic = s->computeKineticEnergy();
    e.potential = s->computePotentialEnergy();
    return e;
  }

 private:
  const Model& m_;
  DartSkeleton dart_;
};

// DART's own reading of a URDF (dart::utils::DartLoader), its speeds matched
// to ours by joint name: one speed each (revolute, continuous, prismatic).
class DartUrdfModel : public EngineModel {
 public:
  DartUrdfModel(const Model& m, const UrdfSource& src) : m_(m) {
    if (!src.floating_joint.empty())
      throw std::runtime_error("its free root is not matched to ours yet");
    if (src.balance_inertia) throw std::runtime_error("it reads the file's own inertias, which --balance-inertia changed");
    dart::utils::DartLoader loader;
    dart::utils::DartLoader::Options options;
    options.mDefaultRootJointType = dart::utils::DartLoader::RootJointType::FIXED;
    loader.setOptions(options);
    QuietDart quiet;
    skel_ = loader.parseSkeletonString(urdfWithoutGeometry(src.text, src.locked), "file:///eigenmass/robot.urdf");
    if (!skel_) throw std::runtime_error("DART did not read the URDF: " + firstLine(quiet.said()));
    skel_->setGravity(m.gravity);
    skel_->setTimeStep(kStateTimeStep);
    // The URDF's joint damping, friction and limits are not the scene's (the
    // import reads none of them; MuJoCo's reading turns them off too).
    for (size_t k = 0; k < skel_->getNumDofs(); ++k) {
      dd::DegreeOfFreedom* f = skel_->getDof(k);
      f->setDampingCoefficient(0);
      f->setSpringStiffness(0);
      f->setCoulombFriction(0);
    }
    for (int i = 0; i < m.n(); ++i) {
      const std::string& name = src.joints[m.bodies[i].file_index];
      const dd::Joint* j = skel_->getJoint(name);
      if (!j || j->getNumDofs() != 1 || m.bodies[i].nu() != 1)
        throw std::runtime_error("joint '" + name + "' is not one speed in DART's reading");
      dof_.push_back(static_cast<int>(j->getIndexInSkeleton(0)));
    }
  }
  EngineEquations at(const Eigen::VectorXd& q, const Eigen::VectorXd& u) override {
    Eigen::VectorXd pos = Eigen::VectorXd::Zero(skel_->getNumDofs()), vel = pos;
    for (int i = 0; i < m_.n(); ++i) pos[dof_[i]] = q[m_.bodies[i].iq], vel[dof_[i]] = u[m_.bodies[i].iu];
    skel_->setPositions(pos);
    skel_->setVelocities(vel);
    const Eigen::MatrixXd M = skel_->getMassMatrix();
    const Eigen::VectorXd C = skel_->getCoriolisAndGravityForces();
    skel_->computeForwardDynamics();
    Eigen::VectorXd a(skel_->getNumDofs());
    readAccelerations(*skel_, a);
    EngineEquations e{Eigen::MatrixXd(m_.nu, m_.nu), Eigen::VectorXd(m_.nu), Eigen::VectorXd(m_.nu), 0, 0};
    for (int i = 0; i < m_.n(); ++i) {
      const int r = m_.bodies[i].iu;
      e.B[r] = -C[dof_[i]];
      e.udot[r] = a[dof_[i]];
      for (int j = 0; j < m_.n(); ++j) e.A(r, m_.bodies[j].iu) = M(dof_[i], dof_[j]);
    }
    e.kinetic = skel_->computeKineticEnergy();
    e.potential = skel_->computePotentialEnergy();
    return e;
  }

 private:
  static std::string firstLine(const std::string& s) { return s.substr(0, s.find('\n')); }
  const Model& m_;
  dd::SkeletonPtr skel_;
  std::vector<int> dof_;  // DART index of body i's speed (internal order)
};

// World::step: DART's semi-implicit Euler (velocities, then positions from
// them), its springs and dampers implicit over the step.
class DartStepper : public FixedStepEngine {
 public:
  DartStepper(const Model& m, const RunSpec& spec) : m_(m), dart_(m), world_(dart::simulation::World::create()) {
    world_->setGravity(m.gravity);
    world_->setTimeStep(spec.dt);
    world_->addSkeleton(dart_.skeleton());
    dart_.setState(m.q0().data(), m.u0().data());
    u_ = m.u0();
    q_ = m.q0();
    if (!m.loops.empty()) {  // DART keeps these per process (static): every run sets them
      const MethodInfo& row = info(spec.method);
      dart::constraint::DynamicJointConstraint::setErrorReductionParameter(row.param("dart_erp", spec.options));
      dart::constraint::DynamicJointConstraint::setConstraintForceMixing(row.param("dart_cfm", spec.options));
    }
    for (const Loop& l : m.loops) addClosure(l);  // assembled: the points meet
    if (m.has_drives || m.has_control) G_.resize(m.nu, m.nu), g_.resize(m.nu), tau_.resize(m.nu), forces_.resize(m.nu);
  }
  std::string step() override {
    addDrives();
    addPointSprings();
    world_->step();  // then clears the forces and commands
    ++evaluations_;  // one forward dynamics per step
    return "";
  }
  long evaluations() const override { return evaluations_; }
  void applyControl(const Eigen::VectorXd& tau) override { control_ = tau; }
  void state(Eigen::VectorXd& q, Eigen::VectorXd& u) override {
    dart_.getState(q, u);
    u_ = u;
  }
  void sample(std::vector<Pose>& poses, double& kinetic, double& potential) override {
    dart_.poses(poses);
    kinetic = dart_.skeleton()->computeKineticEnergy();
    potential = dart_.skeleton()->computePotentialEnergy();
    if (!m_.point_springs.empty()) {  // the point springs' own: DART has none
      dart_.getState(q_, u_);
      formKinematics(m_, q_.data(), u_.data(), ws_);
      potential += pointSpringPotential(m_, ws_);
    }
  }
  void dissipation(double& P, double& Pdot) override {
    if (m_.isMechanism()) {  // P by theory.md eq. (M6); the tree's u' is not the mechanism's, so P' = 0 (the plain trapezoid rule)
      dart_.getState(q_, u_);
      formKinematics(m_, q_.data(), u_.data(), ws_);
      P = nonConservativePower(m_, ws_, u_.data());
      Pdot = 0;
      return;
    }
    const dd::SkeletonPtr& s = dart_.skeleton();
    s->computeForwardDynamics();  // u' at the current state (the step's own is of the state before)
    P = Pdot = 0;
    for (size_t k = 0; k < s->getNumDofs(); ++k) {
      const dd::DegreeOfFreedom* f = s->getDof(k);
      const double c = f->getDampingCoefficient(), v = f->getVelocity();
      P += c * v * v;
      Pdot += 2 * c * v * f->getAcceleration();
    }
  }

 private:
  // A closure as DART's joint constraints between its bodies (the world for the ground).
  void addClosure(const Loop& l) {
    const Attachment& on = l.a.body >= 0 ? l.a : l.b;  // DART's first body is never the world
    const Attachment& other = l.a.body >= 0 ? l.b : l.a;
    dd::BodyNode* first = dart_.node(on.body);
    dd::BodyNode* second = other.body >= 0 ? dart_.node(other.body) : nullptr;
    const Eigen::Isometry3d& T = first->getWorldTransform();  // its frame: ours, at the CM
    const Vec3 axis = T.linear() * (&on == &l.a ? l.axis_a : l.axis_b);
    const auto ball = [&](const Vec3& p) {
      if (second) add(std::make_shared<dart::constraint::BallJointConstraint>(first, second, p));
      else add(std::make_shared<dart::constraint::BallJointConstraint>(first, p));
    };
    const Vec3 p = T * on.point;
    switch (l.type) {
      case LoopType::Ball: ball(p); break;
      case LoopType::Hinge:
        ball(p);
        ball(p + kHingeLever * axis);
        break;
      case LoopType::Weld:
        if (second) add(std::make_shared<dart::constraint::WeldJointConstraint>(first, second));
        else add(std::make_shared<dart::constraint::WeldJointConstraint>(first));
        break;
      case LoopType::Universal:
      case LoopType::Slider:
        throw std::invalid_argument(unmappedLoop(m_, kDartLoops, kDartConstraints));
    }
  }
  void add(const dart::constraint::ConstraintBasePtr& c) { world_->getConstraintSolver()->addConstraint(c); }

  // The drives and a joint controller's held torques as DART's joint forces,
  // G tau (G orthogonal per joint; world_->step() clears them).
  void addDrives() {
    if (!m_.has_drives && !control_.size()) return;
    tau_.setZero();
    for (const Body& b : m_.bodies)
      if (b.joint.torque.size()) tau_.segment(b.iu, b.nu()) = b.joint.torque;
    if (control_.size()) tau_ += control_;
    dart_.speedMap(u_.data(), G_, g_);  // G depends on q alone
    forces_.noalias() = G_ * tau_;
    dart_.skeleton()->setForces(forces_);
  }

  // The point springs as external forces at their points, from DART's poses and velocities.
  void addPointSprings() {
    for (const PointSpring& s : m_.point_springs) {
      const auto at = [&](const Attachment& x, Vec3& p, Vec3& v) {
        if (x.body < 0) return p = x.point, v.setZero(), static_cast<dd::BodyNode*>(nullptr);
        dd::BodyNode* n = dart_.node(x.body);
        p = n->getWorldTransform() * x.point;
        v = n->getLinearVelocity(x.point);  // world frame, the point fixed in the body
        return n;
      };
      Vec3 pa, va, pb, vb;
      dd::BodyNode* na = at(s.a, pa, va);
      dd::BodyNode* nb = at(s.b, pb, vb);
      const Vec3 f = pointSpringForce(s, pa, va, pb, vb);  // on a; -f on b
      if (na) na->addExtForce(f, s.a.point, false, true);
      if (nb) nb->addExtForce(-f, s.b.point, false, true);
    }
  }

  static constexpr double kHingeLever = 1.0;  // m: a hinge's second pair of points, along the axis
  const Model& m_;
  DartSkeleton dart_;
  dart::simulation::WorldPtr world_;
  Eigen::VectorXd q_, u_;
  Workspace ws_{m_};                   // the read-back state's kinematics: point springs, a mechanism's power
  Eigen::MatrixXd G_;                  // (nu x nu): u_D = G u (drives)
  Eigen::VectorXd g_, tau_, forces_;   // (nu): G' u, our drives, DART's joint forces
  Eigen::VectorXd control_;            // (nu): a joint controller's held torques, empty before the first
  long evaluations_ = 0;
};

// dart-udot: DART's u' (forward dynamics) under the in-house integrators.
class DartUdot final : public MethodImpl {
 public:
  explicit DartUdot(const Model& m) : dart_(m) { dart_.skeleton()->setTimeStep(kStateTimeStep); }
  bool needsEquations() const override { return false; }
  bool needsKinematics() const override { return false; }
  Status rates(double, const double* q, const double* u, const Workspace&, const double*, double* udot, double*,
               EvalInfo&) override {
    dart_.setState(q, u);
    dart_.skeleton()->computeForwardDynamics();
    dart_.accelerations(u, udot);
    return {};
  }

 private:
  DartSkeleton dart_;
};

std::unique_ptr<MethodImpl> makeDartUdot(const Model& m, const MethodInfo&, const MethodOptions&) {
  return std::make_unique<DartUdot>(m);
}

// What of DART's crosscheck entries is eigenmass's: the joint springs' and
// dampers' part of B (DART applies them only implicitly inside its step; at a
// state eigenmass evaluates -k (q - q_rest) - c u on DART's stored
// parameters), and a free joint's change of speeds between DART's child frame
// and ours (DartSkeleton::speedMap's bias, accelerations()'s w x v).
EquationsDependence dartDependence(const Model& m) {
  EquationsDependence d;
  const std::string free = jointsOfKinds(m, {JointType::Free});
  const std::string free_line = "the speeds of its joints of kind " + free + " map to ours through eigenmass's change of frame "
                                "(reference/dart.cpp: the bias -R^T (w x v), v' - w x v)";
  if (m.has_springs) d.B = "its joint springs' and dampers' part is eigenmass's -k (q - q_rest) - c u on DART's parameters";
  if (!free.empty()) d.B += (d.B.empty() ? "" : "; ") + free_line, d.udot = free_line;
  return d;
}

}  // namespace

EngineRow dartEngine() {
  EngineRow r;
  r.info.name = "dart";
  r.info.summary = "DART 6.12's World::step: its articulated-body dynamics and semi-implicit Euler, springs and dampers "
                   "implicit, fixed step (what Gazebo runs)";
  r.info.schemes = {{"dart-euler", true, "DART's semi-implicit Euler (World::step: velocities, then positions from them)", "*"}};
  r.info.fixed_scheme = "dart-euler";
  r.info.adaptive_scheme = "dart-euler";  // DART has no adaptive scheme
  r.info.colour = "tab:pink";
  // Its closures' stabilization: DynamicJointConstraint's defaults, read only where loops are.
  r.info.params = {
      {"dart_erp", 0.01, 0, 1, false, "DART: its joint constraints' error reduction parameter (its default 0.01)", nullptr, true},
      {"dart_cfm", 1e-9, 0, 1, false, "DART: its joint constraints' constraint force mixing (its default 1e-9)", nullptr, true}};
  r.code.simulate = [](const Model& m, const CheckedRunSpec& spec, const SampleObserver& observe) {
    QuietDart quiet;
    DartStepper stepper(m, spec);
    return runFixedStep(m, spec, stepper, observe);
  };
  r.code.model = [](const Model& m) -> std::unique_ptr<EngineModel> { return std::make_unique<DartModel>(m); };
  r.code.urdf = [](const Model& m, const UrdfSource& source) -> std::unique_ptr<EngineModel> {
    return std::make_unique<DartUrdfModel>(m, source);
  };
  r.code.version = [] { return std::string(DART_VERSION); };
  r.code.scene_note = [](const Model& m) -> std::string {
    return m.limited.empty() ? "" : "joint limits: DART's JointLimitConstraint in World::step (its position limits enforced; "
                                    "an inelastic stop: no restitution, e is not mapped; its default error allowance and ERP)";
  };
  r.code.limits_refusal = [](const Model& m) -> std::string {  // its joints whose coordinates are ours
    for (const Body& b : m.bodies)
      if (b.joint.limits && b.joint.type != JointType::Revolute && b.joint.type != JointType::Prismatic && b.joint.type != JointType::Universal)
        return std::string("the limits of body '") + b.name + "': DART's limits are mapped on revolute, prismatic and universal joints, not on a " +
               jointTypeName(b.joint.type) + " joint";
    return "";
  };
  r.code.mechanism_refusal = [](const Model& m) { return unmappedLoop(m, kDartLoops, kDartConstraints); };  // point springs and drives all map
  r.code.mechanism_state = "DART's equations at a state are its skeleton's, a mechanism's tree: its joint constraints act "
                           "only as impulses inside World::step, and point springs and drives are applied there; its A is "
                           "judged, its B and u' of a mechanism are not exposed";
  r.code.dependence = dartDependence;
  r.code.udot_method = {"dart-udot", "DART's u' (its articulated-body forward dynamics) under the in-house integrators: DART's "
                                     "formulation apart from its integrator", "#ad4a8c", makeDartUdot};
  return r;
}

}  // namespace em
