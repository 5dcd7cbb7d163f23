#pragma once
/// The immutable model of a tree of rigid bodies: topology (regular numbering,
/// structure matrix T), bodies, joints and the map back to the source's order
/// (docs/theory.md §1–2). Built once by buildModel from bodies listed in any
/// order; reading them from a file is a format's business (io/).
#include <random>
#include <stdexcept>
#include <optional>
#include <string>
#include <vector>

#include "solver/rotation.hpp"

namespace em {

enum class JointType { Revolute, Universal, Gimbal, Ball, Prismatic, Free, Planar };

struct Joint;
using Axes = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 6>;  ///< up to 6 axis columns (free), no heap

/// A kind's kinematics (docs/theory.md §1, §3, §12), one function each,
/// written in the kind's own file, solver/joints/<kind>.cpp; solver/joint.hpp
/// says what each computes. The rotational part turns about the joint point,
/// the sliding part moves it.
struct JointKinematics {
  Mat3 (*rotation)(const Joint& j, const double* q);  ///< R_parent,body
  Vec3 (*slide)(const Joint& j, const double* q);     ///< x, the joint point's displacement (parent frame)
  void (*axes)(const Joint& j, const Mat3& R_p, const double* q, Axes& P);  ///< world axes, slides first
  void (*axis_rates)(const Joint& j, const Axes& P, const Vec3& omega_p, const Vec3& omega_b, const double* u, Axes& Pdot);
  void (*coordinates)(const Joint& j, const Mat3& R, const Vec3& x, const double* near, double* q);  ///< from a pose
  double (*separation)(const Joint& j, const Vec3& x);  ///< the part of x it cannot take
};
extern const JointKinematics kRevoluteKinematics, kUniversalKinematics, kGimbalKinematics, kBallKinematics,
    kPrismaticKinematics, kFreeKinematics, kPlanarKinematics;

/// One row per joint kind: its name (the scene's `type`), how many coordinates
/// and speeds it has, how many of them slide, where its quaternion sits, how many
/// axes a scene gives it, whether a middle angle can lock, and its kinematics
/// (docs/theory.md §1). The sliding coordinates and speeds come first:
/// q = [x (nt), rotation], u = [v (nt), angular (nu - nt)]. A new kind is its
/// value above, its row here and its own file solver/joints/<kind>.cpp; each
/// engine maps it in one place (its mapping table or function), which refuses
/// a kind it has no mapping for.
struct JointTypeInfo {
  JointType type;
  const char* name;
  int nq, nu;  ///< ball: nq 4 (a quaternion), nu 3; free: nq 7, nu 6
  int nt;      ///< translational speeds (prismatic 1, planar 2, free 3), the first nt of u and of q
  int quat;    ///< offset of the unit quaternion [w,x,y,z] in q, -1 without one
  int naxes;   ///< axes in the scene: 1 (key `axis`), 2 (key `axes`, perpendicular) or 0 (the parent's axes)
  bool middle_locks;  ///< a sequence of three angles whose middle one at +-90 deg makes A singular (gimbal)
  const JointKinematics* kinematics;
};
/// The rows in JointType order: inline, so that the per-evaluation loops read
/// a joint's sizes without a call.
inline constexpr JointTypeInfo kJointTypes[] = {
    {JointType::Revolute, "revolute", 1, 1, 0, -1, 1, false, &kRevoluteKinematics},
    {JointType::Universal, "universal", 2, 2, 0, -1, 2, false, &kUniversalKinematics},
    {JointType::Gimbal, "gimbal", 3, 3, 0, -1, 0, true, &kGimbalKinematics},
    {JointType::Ball, "ball", 4, 3, 0, 0, 0, false, &kBallKinematics},
    {JointType::Prismatic, "prismatic", 1, 1, 1, -1, 1, false, &kPrismaticKinematics},
    {JointType::Free, "free", 7, 6, 3, 3, 0, false, &kFreeKinematics},
    {JointType::Planar, "planar", 3, 3, 2, -1, 2, false, &kPlanarKinematics}};
inline const JointTypeInfo& jointRow(JointType t) { return kJointTypes[static_cast<int>(t)]; }
const std::vector<JointTypeInfo>& jointTypeTable();
inline const char* jointTypeName(JointType t) { return jointRow(t).name; }
inline int jointNq(JointType t) { return jointRow(t).nq; }
inline int jointNu(JointType t) { return jointRow(t).nu; }
inline int jointNt(JointType t) { return jointRow(t).nt; }
inline int jointQuat(JointType t) { return jointRow(t).quat; }
inline int jointAxes(JointType t) { return jointRow(t).naxes; }

/// Per-coordinate linear spring-damper, generalized force -k (q - q_rest) - c u.
struct Spring {
  Eigen::VectorXd k, c, q_rest;  // (nu) each
};

/// A point fixed in a body: the body's internal index (-1: the ground) and
/// the point from its CM in the body frame (for the ground, in the world).
struct Attachment {
  int body = -1;
  Vec3 point = Vec3::Zero();
};

/// A closure kind (docs/theory.md §15): its scene name, the equations it adds
/// (its point rows, in m, first; then its direction rows), which axes the
/// scene gives it, whether it holds the relative turn its bodies have at the
/// start (Loop::rel), and its equations (one file each,
/// solver/mechanism/kinds/<kind>.cpp). One row per kind, in LoopType order
/// (static_assert in model.cpp). A new kind is its value here, its row, its own
/// file and, in each engine, its mapping or its refusal by name.
enum class LoopType { Ball, Hinge, Weld, Universal, Slider };
enum class LoopAxes { None, A, AB };  ///< none; axis_a; axis_a and axis_b
struct LoopEquations;  // solver/mechanism/loops.hpp
extern const LoopEquations kBallLoop, kHingeLoop, kWeldLoop, kUniversalLoop, kSliderLoop;
struct LoopTypeInfo {
  LoopType type;
  const char* name;
  int equations;   ///< ball 3, hinge 5, weld 6, universal 4, slider 5
  int point_rows;  ///< the first rows, a point's gap in m: 3 where the points meet, a slider's 2 off its line
  LoopAxes axes;   ///< the axes the scene gives (unit, in a's and b's frames)
  bool holds_turn; ///< keeps b's frame at R_a rel (weld, slider)
  const LoopEquations* equations_of;
};
inline constexpr LoopTypeInfo kLoopTypes[] = {
    {LoopType::Ball, "ball", 3, 3, LoopAxes::None, false, &kBallLoop},
    {LoopType::Hinge, "hinge", 5, 3, LoopAxes::AB, false, &kHingeLoop},
    {LoopType::Weld, "weld", 6, 3, LoopAxes::None, true, &kWeldLoop},
    {LoopType::Universal, "universal", 4, 3, LoopAxes::AB, false, &kUniversalLoop},
    {LoopType::Slider, "slider", 5, 2, LoopAxes::A, true, &kSliderLoop}};
inline const LoopTypeInfo& loopRow(LoopType t) { return kLoopTypes[static_cast<int>(t)]; }

/// One closure of the tree into a mechanism (the scene's `loops`), by its kind:
/// a ball's points meet; a hinge's also keep axis_a (body a's frame) along
/// axis_b (body b's); a universal's keep axis_a square to axis_b; a weld keeps
/// b's frame at the orientation relative to a's that it has at the initial
/// state (rel = R_a^T R_b there); a slider keeps that orientation and b's point
/// on the line through a's point along axis_a.
struct Loop {
  std::string name;
  LoopType type = LoopType::Ball;
  Attachment a, b;
  Vec3 axis_a = Vec3::UnitZ(), axis_b = Vec3::UnitZ();  ///< unit (hinge, universal; slider: axis_a)
  Mat3 rel = Mat3::Identity();                           ///< weld, slider: R_a^T R_b at q0 (set by buildModel)
};

/// A linear spring-damper between two points (the scene's `forces`): tension
/// k (l - length) + c l' along the line from a's point to b's.
struct PointSpring {
  std::string name;
  Attachment a, b;
  double k = 0, c = 0, length = 0;
};

/// What turns a tree into a mechanism, bodies named by their index in the
/// source's list (-1: the ground), as handed to buildModel.
struct MechanismDef {
  std::vector<Loop> loops;
  std::vector<PointSpring> springs;
};

/// A joint's limits (docs/theory.md §17): per coordinate, lower < upper, and
/// Newton's restitution e in [0, 1] at every stop of the joint.
struct JointLimits {
  Eigen::VectorXd lower, upper;  ///< (nq): rad or m
  double restitution = 0;
};

/// A joint-space controller's reference q*(t) (docs/theory.md §18), per
/// coordinate: constant; a sine offset + amplitude sin(2 pi f t); or a table
/// of points (t_i, q_i), linear between them and held beyond its ends.
enum class TargetType { Constant, Sine, Table };
struct ControlTarget {
  TargetType type = TargetType::Constant;
  Eigen::VectorXd q, offset, amplitude, frequency_hz;  ///< (nu) each, as the type uses
  std::vector<double> t;                               ///< table: strictly increasing times (s)
  Eigen::MatrixXd rows;                                ///< table: one row per time  (points x nu)
};

/// A joint's controller (docs/theory.md §18): PD toward a target,
/// tau = clamp(kp (q* - q) + kd (q*' - u), +-effort), or a torque table
/// (t_i, tau_i), linear between points and held beyond its ends. Evaluated at
/// every right-hand side (period 0: continuous) or sampled every `period`
/// seconds from t = 0 and held (zero-order hold); every controlled joint of a
/// model shares one period (one controller).
enum class ControlType { Pd, TorqueTable };
struct JointControl {
  ControlType type = ControlType::Pd;
  Eigen::VectorXd kp, kd, effort;  ///< (nu) each; effort +inf where unclamped
  ControlTarget target;            ///< pd
  std::vector<double> t;           ///< torque table: strictly increasing times (s)
  Eigen::MatrixXd tau;             ///< torque table: one row per time  (points x nu)
  double period = 0;               ///< s; 0: continuous
};

/// One joint: the inboard joint of its body.
struct Joint {
  JointType type = JointType::Revolute;
  Vec3 axis[2] = {Vec3::UnitX(), Vec3::UnitY()};  ///< unit axes, parent frame (revolute, prismatic: [0]; universal, planar: both)
  Vec3 in_parent = Vec3::Zero();  ///< a: parent CM -> joint point, parent frame (world for roots)
  Vec3 in_body = Vec3::Zero();    ///< c: body CM -> joint point, body frame
  Eigen::VectorXd q0, u0;         ///< initial coordinates (nq) and speeds (nu)
  bool has_spring = false;
  Spring spring;
  Eigen::VectorXd torque;         ///< a drive: constant generalized force per speed (nu), empty without one
  std::optional<JointLimits> limits;  ///< stops (joints whose q' = u: no quaternion), else none
  std::optional<JointControl> control;  ///< a joint-space controller (joints whose q' = u), else none
  std::string name;               ///< optional (a URDF joint's): coordinates are then named after it, not the body
  /// Prefix of this joint's coordinate names ("<prefix>.q0"): its name, else the body's.
  const std::string& prefix(const std::string& body) const { return name.empty() ? body : name; }
};

/// A body as handed to buildModel, in its source's order.
struct BodyDef {
  std::string name;
  int parent = -1;                  ///< index of the parent in the same list, -1 for the ground
  double mass = 1.0;
  Mat3 inertia = Mat3::Identity();  ///< about the CM, body frame (matrix entries)
  Joint joint;
};

/// A defect of body `index` (source order) in its `field` ("name", "parent").
struct ModelError : std::invalid_argument {
  ModelError(int index, const std::string& field, const std::string& detail)
      : std::invalid_argument("body " + std::to_string(index) + " " + field + ": " + detail),
        index(index), field(field), detail(detail) {}
  int index;
  std::string field, detail;
};

/// A body of the model, in regular (parents-first) numbering.
struct Body {
  std::string name;
  int parent = -1;        ///< internal index of the parent, -1 for the ground
  double mass = 0;
  Mat3 J;                 ///< inertia about the CM, body frame  (3x3)
  Joint joint;
  int iq = 0, iu = 0;     ///< offsets of this joint's q and u in the internal state
  int file_index = 0;     ///< index in the source's body list
  int file_iq = 0, file_iu = 0;  ///< offsets in the source-order q and u
  std::vector<int> children;
  int nq() const { return jointNq(joint.type); }
  int nu() const { return jointNu(joint.type); }
  int nt() const { return jointNt(joint.type); }
};

/// A coordinate with stops, in internal numbering (Model::limited).
struct LimitedCoordinate {
  int q = 0, u = 0;        ///< its index in q and in u (equal kinds: q' = u on it)
  double lower = 0, upper = 0, restitution = 0;
  std::string name;        ///< "<joint or body>.q<k>"
};

/// Immutable model built once (Pinocchio's Model, MuJoCo's mjModel).
struct Model {
  std::string name;
  Vec3 gravity = Vec3::Zero();
  std::vector<Body> bodies;    ///< regular numbering: parent(i) < i
  int nq = 0, nu = 0;
  bool has_springs = false;    ///< build the joint-force term Q only when declared
  bool has_dampers = false;    ///< some c != 0: runs track the dissipated work W_diss (docs/theory.md §5)
  bool has_gravity = false;
  bool has_sliding = false;    ///< some prismatic or free joint: the formation does translational work only then (theory.md §12)
  bool has_drives = false;     ///< some joint.torque: B gains it, and W_diss counts its work negative (theory.md §15)
  std::vector<Loop> loops;     ///< closures, bodies in internal numbering (theory.md §15)
  std::vector<PointSpring> point_springs;  ///< point-to-point spring-dampers, internal numbering
  int loop_rows = 0;           ///< sum of the loops' equations: the rows of g and G
  std::vector<LimitedCoordinate> limited;  ///< coordinates with stops (joint.limits), internal order
  bool has_control = false;    ///< some joint.control: B gains its torques, and W_diss counts their work negative (theory.md §18)
  double control_period = 0;   ///< the controller's sampling period (s), 0: continuous
  /// Per loop, the speeds its rows can touch (G's nonzero columns): those of
  /// both bodies' paths to the ground, ascending (docs/theory.md §16).
  std::vector<std::vector<int>> loop_speeds;
  Eigen::MatrixXi T;           ///< structure matrix: T(j,i) = 1 if j is i or an ancestor of i  (n x n)
  std::vector<int> file_to_internal;  ///< body index map
  /// Compact copies of bodies[i].parent, .iu and .nu() for the O(n depth)
  /// loops of the formation (MuJoCo's body_parentid, body_dofadr, body_dofnum).  // (n) each
  std::vector<int> body_parent, body_iu, body_nu;
  std::vector<int> body_nt;    ///< translational speeds of body i's joint, the first of its nu  // (n)

  int n() const { return static_cast<int>(bodies.size()); }
  /// Whether it is more than a tree of joint springs: loops, point springs or drives.
  bool isMechanism() const { return !loops.empty() || !point_springs.empty() || has_drives; }
  /// Whether B gains applied forces beyond gravity (joint springs, drives, point springs).
  bool hasAppliedForces() const { return has_springs || has_drives || has_control || !point_springs.empty(); }
  /// Initial state in internal order: q (nq), u (nu).
  Eigen::VectorXd q0() const;
  Eigen::VectorXd u0() const;
  /// Permute an internal-order q (or u) into the source's order.
  void qToFile(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::VectorXd& qf) const;
  void uToFile(const Eigen::Ref<const Eigen::VectorXd>& u, Eigen::VectorXd& uf) const;
  /// Permutation p with (source-order q)[k] = (internal q)[p[k]]; the same for u.
  std::vector<int> qFilePermutation() const;
  std::vector<int> uFilePermutation() const;
  /// Names of coordinates and speeds in source order ("link1.q0", "link1.u0";
  /// a named joint's name in place of the body's).
  std::vector<std::string> qNames() const;
  std::vector<std::string> uNames() const;
  /// Source-order indices of the coordinates that are angles (not a
  /// quaternion's, not a displacement): what a coordinate error in rad compares.
  std::vector<int> angleCoordinates() const;
};

/// The same model started at (q, u), internal order (an assembled start:
/// solver/mechanism/assembly.hpp); its loops keep the turns they hold (rel).
Model withInitialState(Model m, const Eigen::VectorXd& q, const Eigen::VectorXd& u);

/// Bounds of a state (a scene's q0 and u0, an ensemble's members, a state
/// handed to the Python module): at 1e4 rad (m) a double still resolves
/// 1.8e-12 rad (m); at 1e6 rad/s (m/s) a step of 1e-3 s turns a joint 160
/// times and u^2 keeps every energy finite. A quaternion is a unit one within
/// kUnitQuatTol.
inline constexpr double kMaxAngle = 1e4;
inline constexpr double kMaxDisplacement = 1e4;
inline constexpr double kMaxSpeed = 1e6;
inline constexpr double kUnitQuatTol = 1e-6;
/// The first coordinate or speed of an internal-order state beyond the bounds,
/// named as the outputs name it ("q link2.q0: angle 1.00027e+04 rad beyond
/// +-10000 rad", "u link2.u0: speed not finite"), or "" when every one is within.
/// // q: (nq), u: (nu)
std::string beyondStateBounds(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u);

/// Validate the topology and renumber parents-first (docs/theory.md §1–2):
/// O(n), no recursion. Throws ModelError naming the body (source index) and
/// the field: an empty or duplicate name, a parent out of range, a body that
/// is its own parent or does not reach the ground (a cycle), a coordinate
/// prefix (joint name, else body name) used twice (field "joint.name").
Model buildModel(const std::string& name, const Vec3& gravity, const std::vector<BodyDef>& bodies,
                 const MechanismDef& mechanism = {});

/// A random state in internal order, for checks at states a run may never
/// reach: angles uniform in [-pi, pi] (a gimbal's middle angle within +-72 deg,
/// away from its lock, where A is singular), unit quaternions uniform on the
/// sphere, displacements uniform in [-1, 1] m, speeds uniform in [-2, 2] rad/s
/// (or m/s).  // q: (nq), u: (nu)
void randomState(const Model& m, std::mt19937& rng, Eigen::VectorXd& q, Eigen::VectorXd& u);

}  // namespace em
