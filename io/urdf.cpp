#include "io/urdf.hpp"

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <set>

#include "io/digest.hpp"
#include "io/json_input.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

using Err = InputError;
using json = nlohmann::json;

// The scene loader's tolerance (io/scene_json.cpp): equality in a triangle
// inequality (a thin plate) passes despite the rounding of written decimals.
constexpr double kInertiaRelTol = 1e-9;

std::string linkAt(const std::string& n) { return "link '" + printable(n, 40) + "'"; }
std::string jointAt(const std::string& n) { return "joint '" + printable(n, 40) + "'"; }

Vec3 vec(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }
Mat3 rotation(const urdf::Rotation& r) { return Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix(); }

// liburdfdom reports through console_bridge: keep its errors for the
// one-line message and let nothing else reach the terminal.
struct CapturedLog : console_bridge::OutputHandler {
  std::string errors;
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors += (errors.empty() ? "" : "; ") + text;
  }
};

// Whether `e` or an element under it is a xacro element (<xacro:...>).
// Comments are not elements: expanded files such as PAL's TALOS keep
// `<xacro:...>` text inside comments, and the namespace declaration too.
bool hasXacroElement(const TiXmlElement* e) {
  for (; e; e = e->NextSiblingElement()) {
    if (std::string(e->Value()).rfind("xacro:", 0) == 0) return true;
    if (hasXacroElement(e->FirstChildElement())) return true;
  }
  return false;
}

urdf::ModelInterfaceSharedPtr parse(const std::string& text) {
  // A xacro file parses as XML but its macros are not URDF: say what to do.
  TiXmlDocument doc;
  doc.Parse(text.c_str());
  if (!doc.Error() && hasXacroElement(doc.RootElement()))
    throw Err("(urdf)", "a xacro file (xacro: elements): expand it first, `xacro FILE.xacro > FILE.urdf`");
  CapturedLog log;
  console_bridge::useOutputHandler(&log);
  urdf::ModelInterfaceSharedPtr m;
  try {
    m = urdf::parseURDF(text);
  } catch (const std::exception& e) {
    log.errors = e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  // liburdfdom logs some defects and goes on with a default in their place
  // (an inertial it cannot read becomes all zeros): any error refuses the file.
  if (!m || !log.errors.empty())
    throw Err("(urdf)", log.errors.empty() ? "not a valid URDF" : printable(log.errors, 240));
  return m;
}

// A closed loop makes liburdfdom's links own each other through shared
// pointers (a cycle nothing frees): when the import is done, whatever its
// outcome, every link lets go of its children.
struct ModelGuard {
  urdf::ModelInterfaceSharedPtr model;
  ~ModelGuard() {
    for (auto& [name, link] : model->links_) {
      link->child_links.clear();
      link->child_joints.clear();
    }
  }
};

// Joint names in the order the file lists them (liburdfdom keeps a map by name).
std::vector<std::string> jointsInFileOrder(const std::string& text) {
  TiXmlDocument doc;
  doc.Parse(text.c_str());
  std::vector<std::string> names;
  const TiXmlElement* robot = doc.RootElement();  // liburdfdom has parsed the same text
  for (const TiXmlElement* j = robot ? robot->FirstChildElement("joint") : nullptr; j; j = j->NextSiblingElement("joint"))
    if (const char* n = j->Attribute("name")) names.push_back(n);
  return names;
}

// A name as scenes allow it: characters outside letters, digits, '_' and '-' become '_'.
std::string sceneName(const std::string& urdf_name, const std::string& where) {
  std::string n = urdf_name;
  for (char& c : n)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) c = '_';
  if (!isSceneName(n)) throw Err(where, "name longer than 64 characters, the most a scene allows");
  return n;
}

/// A link frame in the world at the zero configuration.
struct Frame {
  Mat3 R = Mat3::Identity();
  Vec3 p = Vec3::Zero();
};

/// A mass in the world at the zero configuration: m, CM c, inertia J about c (world axes).
struct MassPart {
  double m = 0;
  Vec3 c = Vec3::Zero();
  Mat3 J = Mat3::Zero();
};

// Principal moments, ascending, of a symmetric 3x3 matrix.
Vec3 principal(const Mat3& J) { return Eigen::SelfAdjointEigenSolver<Mat3>(J).eigenvalues(); }

std::string moments(const Vec3& I) { return gnum(I[0]) + ", " + gnum(I[1]) + ", " + gnum(I[2]); }

// A link's inertia as written (its inertial frame), checked; repaired the way
// MuJoCo's balanceinertia does when the user asks for it.
Mat3 linkInertia(const urdf::Inertial& in, const std::string& link, const UrdfOptions& opt,
                 std::vector<std::string>& notes) {
  Mat3 J;
  J << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  if (!std::isfinite(in.mass) || !J.allFinite()) throw Err(linkAt(link), "mass or inertia not a finite number");
  if (in.mass < 0) throw Err(linkAt(link), "negative mass " + gnum(in.mass));
  if (in.mass == 0) {
    if (!J.isZero(0)) throw Err(linkAt(link), "mass 0 with a nonzero inertia");
    return J;
  }
  const Vec3 I = principal(J);
  const double scale = I.cwiseAbs().maxCoeff();
  if (I[0] < -kInertiaRelTol * scale)
    throw Err(linkAt(link), "inertia not positive semi-definite (principal moments " + moments(I) + ")");
  if (I[0] + I[1] >= I[2] * (1 - kInertiaRelTol)) return J;
  const std::string broken = "principal moments " + gnum(I[0]) + " + " + gnum(I[1]) + " < " + gnum(I[2]);
  if (!opt.balance_inertia)
    throw Err(linkAt(link), "inertia violates the triangle inequality (" + broken +
                                "); --balance-inertia sets such moments to their mean, as MuJoCo's balanceinertia");
  const double mean = I.sum() / 3;
  notes.push_back(linkAt(link) + ": " + broken + " (triangle inequality): set to their mean " + gnum(mean, 9) +
                  " (--balance-inertia)");
  return mean * Mat3::Identity();
}

// Mass, CM and inertia about the CM of parts rigidly joined (parallel-axis theorem).
MassPart combine(const std::vector<MassPart>& parts) {
  MassPart s;
  for (const MassPart& p : parts) {
    s.m += p.m;
    s.c += p.m * p.c;
  }
  if (!(s.m > 0)) return s;
  s.c /= s.m;
  for (const MassPart& p : parts) {
    const Vec3 d = p.c - s.c;
    s.J += p.J + p.m * (d.squaredNorm() * Mat3::Identity() - d * d.transpose());
  }
  return s;
}

// A URDF joint kind as a scene's, the one mapping of kinds; nothing for a kind
// a scene has not (a fixed joint is merged, not mapped).
std::optional<JointType> sceneKind(const urdf::Joint& j) {
  switch (j.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS: return JointType::Revolute;
    case urdf::Joint::PRISMATIC: return JointType::Prismatic;
    case urdf::Joint::PLANAR: return JointType::Planar;
    case urdf::Joint::FLOATING: return JointType::Free;
    default: return std::nullopt;
  }
}

// How a URDF joint enters the scene: a moving joint, or merged (held at zero).
bool isMoving(const urdf::Joint& j, const std::set<std::string>& locked) {
  if (locked.count(j.name) || j.type == urdf::Joint::FIXED) return false;
  if (j.mimic)
    throw Err(jointAt(j.name), "mimic joints couple two coordinates, which independent tree joints cannot express "
                               "(--lock-joint " + j.name + " holds it at zero)");
  if (sceneKind(j)) return true;
  throw Err(jointAt(j.name), "unknown joints are not supported: scenes have revolute, prismatic, planar and free "
                             "joints (--lock-joint " + j.name + " holds it at zero)");
}

// A planar joint's in-plane axes from its plane normal n (carrier frame) and
// the joint frame's x axis there: e1 along x's part in the plane (y's where x
// is along n), e2 = n x e1, so that e1 x e2 = n (docs/urdf.md).
void planarAxes(const Vec3& n, const Mat3& frame, Joint& j) {
  Vec3 e1 = frame.col(0) - n.dot(frame.col(0)) * n;
  if (e1.norm() < 1e-6) e1 = frame.col(1) - n.dot(frame.col(1)) * n;
  j.axis[0] = e1.normalized();
  j.axis[1] = n.cross(j.axis[0]);
}

/// The robot at its zero configuration: link frames, which moving link
/// carries each link ("" for the ground) and each carrier's mass parts.
struct Walk {
  std::map<std::string, Frame> frame;
  std::map<std::string, std::string> carrier;
  std::map<std::string, std::vector<MassPart>> parts;
  std::map<std::string, std::vector<std::string>> merged;  ///< carrier -> links merged into it
  std::vector<std::string> ground_links;                  ///< the root and what is fixed to it
};

void addMass(const urdf::Link& l, const std::string& carrier, const UrdfOptions& opt, Walk& w,
             std::vector<std::string>& notes) {
  if (carrier.empty()) {
    w.ground_links.push_back(l.name);
    return;  // held by the ground: its mass never moves
  }
  if (carrier != l.name) w.merged[carrier].push_back(l.name);
  if (!l.inertial) return;
  const Frame& F = w.frame[l.name];
  const Mat3 J = linkInertia(*l.inertial, l.name, opt, notes);
  const Mat3 R = F.R * rotation(l.inertial->origin.rotation);
  w.parts[carrier].push_back({l.inertial->mass, F.p + F.R * vec(l.inertial->origin.position), R * J * R.transpose()});
}

// Depth-first from the root with an explicit stack (no recursion on a depth the file chooses).
Walk walk(const urdf::ModelInterface& u, const std::set<std::string>& locked, const UrdfOptions& opt,
          std::vector<std::string>& notes) {
  Walk w;
  const std::string root = u.getRoot()->name;
  w.frame[root] = Frame{};
  w.carrier[root] = opt.floating_base ? root : "";
  std::vector<urdf::LinkConstSharedPtr> stack = {u.getRoot()};
  std::set<std::string> reached = {root};
  while (!stack.empty()) {
    const urdf::LinkConstSharedPtr l = stack.back();
    stack.pop_back();
    addMass(*l, w.carrier[l->name], opt, w, notes);
    for (const urdf::JointSharedPtr& j : l->child_joints) {
      // liburdfdom lets a second joint into the same child pass: a closed loop.
      if (!reached.insert(j->child_link_name).second)
        throw Err(jointAt(j->name), "link '" + printable(j->child_link_name, 40) +
                                        "' is reached a second time: a closed loop, which a tree cannot express");
      const Frame& F = w.frame[l->name];
      const urdf::Pose& o = j->parent_to_joint_origin_transform;
      w.frame[j->child_link_name] = {F.R * rotation(o.rotation), F.p + F.R * vec(o.position)};
      w.carrier[j->child_link_name] = isMoving(*j, locked) ? j->child_link_name : w.carrier[l->name];
    }
    for (auto it = l->child_links.rbegin(); it != l->child_links.rend(); ++it) stack.push_back(*it);
  }
  return w;
}

// The carrier's mass properties, which must make a body that can turn about any axis.
MassPart bodyMass(const Walk& w, const std::string& link) {
  const auto it = w.parts.find(link);
  const MassPart s = combine(it == w.parts.end() ? std::vector<MassPart>{} : it->second);
  const std::string with = w.merged.count(link) ? " (with the links fixed to it)" : "";
  if (!(s.m > 0)) throw Err(linkAt(link), "no mass" + with + ": a moving link needs mass and inertia");
  if (!(s.m >= kMassMin && s.m <= kMassMax))
    throw Err(linkAt(link), "mass" + with + " " + gnum(s.m) + " kg outside [" + gnum(kMassMin) + ", " + gnum(kMassMax) + "]");
  const Vec3 I = principal(s.J);
  if (!(I[0] > kInertiaRelTol * I[2]))
    throw Err(linkAt(link), "inertia about the CM" + with + " not positive definite (principal moments " + moments(I) + ")");
  if (!(I[2] >= kInertiaMin && I[2] <= kInertiaMax))
    throw Err(linkAt(link), "inertia about the CM" + with + ": largest principal moment " + gnum(I[2]) + " kg m^2 outside [" +
                                gnum(kInertiaMin) + ", " + gnum(kInertiaMax) + "]");
  return s;
}

std::set<std::string> lockedJoints(const urdf::ModelInterface& u, const UrdfOptions& opt, std::vector<std::string>& notes) {
  std::set<std::string> locked;
  for (const std::string& name : opt.lock_joints) {
    if (!u.getJoint(name)) throw Err("--lock-joint", "no joint named '" + printable(name, 40) + "'");
    if (u.getJoint(name)->type == urdf::Joint::FIXED) throw Err("--lock-joint", jointAt(name) + " is fixed already: nothing to lock");
    if (!locked.insert(name).second) throw Err("--lock-joint", jointAt(name) + " is named twice");
    notes.push_back(jointAt(name) + ": held at zero (--lock-joint)");
  }
  return locked;
}

// A scene body carried by `link` (joint point at its frame's origin), hanging
// from `parent` ("" for the ground), its joint of `type` not yet set.
BodySpec linkBody(const std::string& link, const std::string& parent, const std::string& joint, const Walk& w,
                  const std::map<std::string, MassPart>& mass) {
  const Frame& F = w.frame.at(link);
  const MassPart& m = mass.at(link);
  BodySpec b;
  b.name = sceneName(link, linkAt(link));
  b.parent = parent.empty() ? "ground" : sceneName(parent, linkAt(parent));
  b.mass = m.m;
  b.inertia = m.J;
  b.joint.name = sceneName(joint, jointAt(joint));
  b.joint.in_parent = parent.empty() ? F.p : Vec3(F.p - mass.at(parent).c);
  b.joint.in_body = F.p - m.c;
  b.extra = {{"x-urdf-link", link}, {"x-urdf-joint", joint}};
  if (w.merged.count(link)) b.extra["x-urdf-merged-links"] = w.merged.at(link);
  return b;
}

// The free root's joint name: floating_base, or floating_base_2, _3, ... where the URDF
// names a joint so (Unitree's A1 has a fixed joint 'floating_base' between base and trunk).
std::string floatingJointName(const urdf::ModelInterface& u) {
  std::string name = kFloatingBaseJoint;
  for (int k = 2; u.getJoint(name); ++k) name = std::string(kFloatingBaseJoint) + "_" + std::to_string(k);
  return name;
}

// --floating-base on a root that already holds its base by a URDF floating joint (a massless
// 'world' above the robot, as Unitree's AS2): the base floats without the option.
void refuseFloatingTwice(const urdf::Link& root) {
  for (const urdf::JointSharedPtr& j : root.child_joints)
    if (j->type == urdf::Joint::FLOATING && !root.inertial)
      throw Err("--floating-base", linkAt(root.name) + " (no mass) holds " + linkAt(j->child_link_name) + " by the floating " +
                                      jointAt(j->name) + " already: import without --floating-base, and that link floats");
}

void setFree(Joint& j) {
  j.type = JointType::Free;
  j.q0 = Eigen::VectorXd::Zero(7);
  j.q0[3] = 1;  // identity quaternion
  j.u0 = Eigen::VectorXd::Zero(6);
}

// The scene body of moving joint j: joint point and axis from the child link's frame.
BodySpec body(const urdf::Joint& j, const Walk& w, const std::map<std::string, MassPart>& mass) {
  const std::string& link = j.child_link_name;
  BodySpec b = linkBody(link, w.carrier.at(j.parent_link_name), j.name, w, mass);
  if (j.type == urdf::Joint::FLOATING) {
    setFree(b.joint);
    return b;
  }
  b.joint.type = *sceneKind(j);
  const Mat3& frame = w.frame.at(link).R;  // the joint frame, in the carrier's
  const Vec3 axis = frame * vec(j.axis);
  if (!(axis.stableNorm() > 0)) throw Err(jointAt(j.name), "zero axis");
  b.joint.axis[0] = axis.stableNormalized();
  if (b.joint.type == JointType::Planar) planarAxes(Vec3(b.joint.axis[0]), frame, b.joint);
  b.joint.q0 = b.joint.u0 = Eigen::VectorXd::Zero(jointNq(b.joint.type));
  return b;
}

// The joint dynamics a user asked for (docs/urdf.md, "Dynamics"): <dynamics
// damping> as a damper (--urdf-damping; a friction it cannot model refused
// unless --urdf-ignore-friction), <limit lower upper> as stops
// (--urdf-limits E), each noted.
void importDynamics(const urdf::Joint& j, const UrdfOptions& opt, BodySpec& b, std::vector<std::string>& notes) {
  const int nu = jointNu(b.joint.type);
  if (opt.damping && j.dynamics) {
    if (j.dynamics->friction != 0 && !opt.ignore_friction)
      throw Err(jointAt(j.name), "<dynamics friction=\"" + gnum(j.dynamics->friction) +
                                     "\"> is not modelled (Coulomb friction): --urdf-ignore-friction runs without it, noted");
    if (j.dynamics->friction != 0) notes.push_back(jointAt(j.name) + ": <dynamics friction> " + gnum(j.dynamics->friction) + " not modelled (--urdf-ignore-friction)");
    if (!(j.dynamics->damping >= 0 && j.dynamics->damping <= kMaxForceCoefficient))
      throw Err(jointAt(j.name), "<dynamics damping=\"" + gnum(j.dynamics->damping) + "\"> outside [0, " + gnum(kMaxForceCoefficient) + "]");
    if (j.dynamics->damping > 0) {
      b.joint.has_spring = true;
      b.joint.spring = {Eigen::VectorXd::Zero(nu), Eigen::VectorXd::Constant(nu, j.dynamics->damping), Eigen::VectorXd::Zero(nu)};
    }
  }
  const bool bounded = j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::PRISMATIC;
  if (opt.limits_restitution && bounded && j.limits) {
    const double lo = j.limits->lower, hi = j.limits->upper;
    if (!(lo < hi)) throw Err(jointAt(j.name), "<limit lower=\"" + gnum(lo) + "\" upper=\"" + gnum(hi) + "\">: lower is not below upper");
    if (!(lo <= 0 && hi >= 0))
      throw Err(jointAt(j.name), "its start q = 0 lies outside <limit> [" + gnum(lo) + ", " + gnum(hi) + "]");
    b.joint.limits = JointLimits{Eigen::VectorXd::Constant(1, lo), Eigen::VectorXd::Constant(1, hi), *opt.limits_restitution};
  }
}

// A URDF joint's <limit effort> (N m or N), for a controller whose "effort" is "urdf".
std::optional<double> urdfEffort(const urdf::Joint& j) {
  if (!j.limits || !(j.limits->effort > 0)) return std::nullopt;
  return j.limits->effort;
}

// --control FILE: {"format": "eigenmass-control/1", "joints": {"<URDF joint>": <a scene's joint.control>}}.
void importControl(const urdf::ModelInterface& u, const std::string& file, const std::vector<std::string>& joints,
                   std::vector<BodySpec>& bodies, std::vector<std::string>& notes) {
  const json doc = readJsonFile(file, "control file");
  const auto where = [&file](const std::string& key) { return "--control " + file + ": " + key; };
  if (!doc.is_object() || doc.value("format", json()) != "eigenmass-control/1")
    throw Err(where("format"), "expected \"eigenmass-control/1\"");
  onlyKeys(doc, where(""), {"format", "joints"});
  if (!doc.contains("joints") || !doc["joints"].is_object() || doc["joints"].empty())
    throw Err(where("joints"), "expected an object of controllers by URDF joint name");
  const std::string* first = nullptr;  // the first controlled joint: every other shares its period
  for (auto it = doc["joints"].begin(); it != doc["joints"].end(); ++it) {
    const auto at = std::find(joints.begin(), joints.end(), it.key());
    if (at == joints.end()) throw Err(where(jsonPath("joints", it.key())), "no moving joint of that name in the robot");
    BodySpec& b = bodies[static_cast<size_t>(at - joints.begin())];
    const std::optional<double> effort = urdfEffort(*u.getJoint(it.key()));
    b.joint.control = parseJointControl(it.value(), where(jsonPath("joints", it.key())), b.joint, effort);
    if (!first) first = &it.key();
    else if (b.joint.control->period != bodies[static_cast<size_t>(std::find(joints.begin(), joints.end(), *first) - joints.begin())].joint.control->period)
      throw Err(where(jsonPath(jsonPath("joints", it.key()), "period")),
                "differs from joint '" + printable(*first, 40) + "''s: every controlled joint shares one period (one controller; absent: continuous)");
  }
  notes.push_back("joint controllers from " + file + " (" + std::to_string(doc["joints"].size()) + " joints)");
}

// Two URDF names that become one scene name would make two bodies (or coordinates) one.
void requireDistinct(const std::vector<BodySpec>& bodies, const std::vector<std::string>& joints) {
  std::map<std::string, std::string> seen;
  for (size_t i = 0; i < bodies.size(); ++i) {
    const std::string link = bodies[i].extra.at("x-urdf-link");
    for (const auto& [name, what] : {std::pair{bodies[i].name, linkAt(link)}, {bodies[i].joint.name, jointAt(joints[i])}}) {
      auto [it, fresh] = seen.emplace(name, what);
      if (!fresh && it->second != what)
        throw Err(what, "its scene name '" + name + "' is also that of " + it->second);
    }
  }
}

}  // namespace

bool isUrdfPath(const std::string& path) {
  if (path.size() < 5) return false;
  std::string ext = path.substr(path.size() - 5);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".urdf";
}

UrdfScene importUrdf(const std::string& text, const std::string& source, const UrdfOptions& opt) {
  const ModelGuard guard{parse(text)};
  const urdf::ModelInterfaceSharedPtr& u = guard.model;
  UrdfScene s;
  const std::set<std::string> locked = lockedJoints(*u, opt, s.notes);
  const Walk w = walk(*u, locked, opt, s.notes);
  for (const std::string& name : jointsInFileOrder(text)) {
    const urdf::JointConstSharedPtr j = u->getJoint(name);
    if (!j || w.carrier.at(j->child_link_name) != j->child_link_name) continue;  // merged
    s.joint_names.push_back(name);
  }
  if (opt.floating_base) refuseFloatingTwice(*u->getRoot());  // before the root's mass is asked for
  // A body's joint point is placed from its parent's CM: every moving link's mass first.
  std::map<std::string, MassPart> mass;
  for (const auto& [link, carrier] : w.carrier)
    if (!carrier.empty() && carrier == link) mass.emplace(link, bodyMass(w, link));
  for (const std::string& name : s.joint_names) s.spec.bodies.push_back(body(*u->getJoint(name), w, mass));
  if (opt.floating_base) {  // the root link first, on its free joint at its frame's origin
    const std::string root = u->getRoot()->name, joint = floatingJointName(*u);
    s.spec.bodies.insert(s.spec.bodies.begin(), linkBody(root, "", joint, w, mass));
    setFree(s.spec.bodies.front().joint);
    s.joint_names.insert(s.joint_names.begin(), joint);
    s.notes.push_back(linkAt(root) + ": moves on a free joint '" + joint + "' (--floating-base" +
                      (joint == kFloatingBaseJoint ? "" : std::string("; the URDF has a joint named '") + kFloatingBaseJoint + "'") + ")");
  }
  if (s.spec.bodies.empty()) throw Err("(urdf)", "no revolute, continuous, prismatic, planar or floating joint: nothing moves");
  for (size_t i = 0; i < s.joint_names.size(); ++i)
    if (const urdf::JointConstSharedPtr j = u->getJoint(s.joint_names[i]); j) importDynamics(*j, opt, s.spec.bodies[i], s.notes);
  if (opt.damping) s.notes.push_back("<dynamics damping> imported as joint dampers (--urdf-damping)");
  if (opt.limits_restitution) s.notes.push_back("<limit lower upper> imported as stops of restitution " + gnum(*opt.limits_restitution) + " (--urdf-limits)");
  if (!opt.control_file.empty()) importControl(*u, opt.control_file, s.joint_names, s.spec.bodies, s.notes);
  requireDistinct(s.spec.bodies, s.joint_names);
  s.spec.name = sceneName(u->getName(), "robot name");
  s.spec.extra = {{"x-source", {{"format", "urdf"}, {"file", source}, {"sha256", sha256Hex(text)}, {"robot", u->getName()}}},
                  {"x-urdf-ground-links", w.ground_links},
                  {"x-urdf-gravity", "URDF states none: the scene's default, 9.81 m/s^2 along -z (URDF's z up)"}};
  if (!s.notes.empty()) s.spec.extra["x-urdf-notes"] = s.notes;
  return s;
}

}  // namespace em
