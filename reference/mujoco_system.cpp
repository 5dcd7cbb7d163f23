#include "reference/mujoco_system.hpp"

#include "reference/urdf_text.hpp"

#include <cstdio>
#include <set>
#include <sstream>
#include <stdexcept>

#include <mujoco/mujoco.h>
#include <tinyxml.h>

namespace em {

namespace {

std::string vec(const Vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g", v.x(), v.y(), v.z());
  return buf;
}

// Diagonal inertias as diaginertia: MuJoCo's compiler diagonalizes a full one
// (to 1e-12 absolute), which would perturb A by ~1e-9 on small links.
std::string inertial(const Body& b) {
  const Mat3& J = b.J;
  char buf[256];
  if (J(0, 1) == 0 && J(0, 2) == 0 && J(1, 2) == 0)
    std::snprintf(buf, sizeof buf, "<inertial pos=\"0 0 0\" mass=\"%.17g\" diaginertia=\"%s\"/>", b.mass,
                  vec(J.diagonal()).c_str());
  else
    std::snprintf(buf, sizeof buf,
                  "<inertial pos=\"0 0 0\" mass=\"%.17g\" fullinertia=\"%.17g %.17g %.17g %.17g %.17g %.17g\"/>", b.mass,
                  J(0, 0), J(1, 1), J(2, 2), J(0, 1), J(0, 2), J(1, 2));
  return buf;
}

// One MuJoCo joint of body b, named after its first in-house coordinate k;
// a one-coordinate joint carries coordinate k's spring and damper (MuJoCo's
// passive force -stiffness (q - springref) - damping u, as ours).
void mjJoint(std::ostream& o, const Body& b, int k, const char* type, const Vec3& axis) {
  o << "<joint name=\"" << b.name << ".q" << k << "\" type=\"" << type << "\" pos=\"" << vec(b.joint.in_body) << "\" axis=\""
    << vec(axis) << "\"";
  if (b.joint.has_spring && std::string(type) != "ball") {
    const Spring& s = b.joint.spring;
    char buf[160];
    std::snprintf(buf, sizeof buf, " stiffness=\"%.17g\" damping=\"%.17g\" springref=\"%.17g\"", s.k[k], s.c[k], s.q_rest[k]);
    o << buf;
  }
  if (const auto& l = b.joint.limits) {  // a soft limit at MuJoCo's default solreflimit and solimplimit
    char buf[120];
    std::snprintf(buf, sizeof buf, " limited=\"true\" range=\"%.17g %.17g\"", l->lower[k], l->upper[k]);
    o << buf;
  }
  o << "/>";
}

// A joint kind as MuJoCo joints, the one mapping of kinds: the joints it
// becomes in one MJCF body, applied in order about the turned axes (type and
// axis each, the axis in the parent's frame at zero coordinates), and the
// type MuJoCo's own URDF reader makes of a URDF joint of this kind (nullptr:
// a URDF has no such joint, or MuJoCo's reading is not matched to ours).
struct MjJoints {
  std::vector<std::pair<const char*, Vec3>> joints;
  const char* from_urdf = nullptr;
};

MjJoints mjJoints(const Joint& j) {
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  switch (j.type) {
    case JointType::Revolute: return {{{"hinge", j.axis[0]}}, "hinge"};
    case JointType::Universal: return {{{"hinge", j.axis[0]}, {"hinge", j.axis[1]}}};
    case JointType::Gimbal: return {{{"hinge", x}, {"hinge", y}, {"hinge", z}}};  // Rx Ry Rz
    case JointType::Ball: return {{{"ball", z}}};
    case JointType::Prismatic: return {{{"slide", j.axis[0]}}, "slide"};
    // Three slides and a ball: MuJoCo's free joint must hang from the world (from a URDF it does).
    case JointType::Free: return {{{"slide", x}, {"slide", y}, {"slide", z}, {"ball", z}}, "free"};
    case JointType::Planar: return {{{"slide", j.axis[0]}, {"slide", j.axis[1]}, {"hinge", j.axis[0].cross(j.axis[1])}}};
  }
  throw std::logic_error("MuJoCo: a joint kind without a mapping");
}

// The in-house joint as MuJoCo joints, named after its first in-house coordinate each.
void joints(std::ostream& o, const Body& b) {
  int k = 0;
  for (const auto& [type, axis] : mjJoints(b.joint).joints) {
    mjJoint(o, b, k, type, axis);
    k += std::string(type) == "ball" ? 4 : 1;  // our coordinates: a ball's quaternion takes four
  }
}

// A mechanism's closures as MuJoCo connect equalities (docs/reference-engines.md,
// "Mechanisms"): a ball is one, a hinge two (the points, and the points one
// lever along the axes), a weld three (the points, and one lever along a's x
// and y, held by b where the weld holds them). MuJoCo's compiler computes body
// 2's anchor at qpos0; eq_data is rewritten after compiling with both anchors
// as the scene gives them (each body's frame is at its CM, as ours).
constexpr double kLever = 1.0;  // m: the second and third points' distance along the axes
struct MjConnect {
  int a, b;      // internal bodies, -1 the ground (MuJoCo's world)
  Vec3 pa, pb;   // anchors in a's and b's frames
};
std::vector<MjConnect> mjConnects(const Model& m) {
  std::vector<MjConnect> out;
  for (const Loop& l : m.loops) {
    const auto add = [&](const Vec3& da, const Vec3& db) { out.push_back({l.a.body, l.b.body, l.a.point + da, l.b.point + db}); };
    add(Vec3::Zero(), Vec3::Zero());
    switch (l.type) {
      case LoopType::Ball: break;
      case LoopType::Hinge: add(kLever * l.axis_a, kLever * l.axis_b); break;
      case LoopType::Weld:  // a vector d of a's frame is rel^T d in b's at the weld (R_b = R_a rel)
        for (const Vec3& d : {Vec3(kLever * Vec3::UnitX()), Vec3(kLever * Vec3::UnitY())}) add(d, l.rel.transpose() * d);
        break;
      case LoopType::Universal:
      case LoopType::Slider:
        throw std::invalid_argument(unmappedLoop(m, kMjLoops, "MuJoCo 2.2's equality constraints (connect, weld)"));
    }
  }
  return out;
}

// A point spring's two ends as MuJoCo sites: "<spring>.a" on body a, "<spring>.b" on body b.
struct MjSite {
  std::string name;
  Vec3 pos;
};
std::vector<std::vector<MjSite>> mjSites(const Model& m) {  // [body + 1]: [0] the world
  std::vector<std::vector<MjSite>> out(m.n() + 1);
  for (size_t k = 0; k < m.point_springs.size(); ++k) {
    const PointSpring& s = m.point_springs[k];
    out[s.a.body + 1].push_back({"ps" + std::to_string(k) + ".a", s.a.point});
    out[s.b.body + 1].push_back({"ps" + std::to_string(k) + ".b", s.b.point});
  }
  return out;
}

void sites(std::ostream& o, const std::vector<MjSite>& list) {
  for (const MjSite& s : list) o << "<site name=\"" << s.name << "\" pos=\"" << vec(s.pos) << "\"/>";
}

// The equalities and tendons of a mechanism (empty for a tree).
std::string mechanismXml(const Model& m) {
  std::ostringstream o;
  const auto name = [&](int body) { return body < 0 ? std::string("world") : m.bodies[body].name; };
  const std::vector<MjConnect> connects = mjConnects(m);
  if (!connects.empty()) {
    o << "<equality>";
    for (const MjConnect& c : connects)
      o << "<connect body1=\"" << name(c.a) << "\" body2=\"" << name(c.b) << "\" anchor=\"" << vec(c.pa) << "\"/>";
    o << "</equality>";
  }
  if (!m.point_springs.empty()) {
    o << "<tendon>";
    for (size_t k = 0; k < m.point_springs.size(); ++k) {
      const PointSpring& s = m.point_springs[k];
      char buf[200];
      std::snprintf(buf, sizeof buf, " stiffness=\"%.17g\" damping=\"%.17g\" springlength=\"%.17g\"", s.k, s.c, s.length);
      o << "<spatial name=\"" << s.name << "\"" << buf << "><site site=\"ps" << k << ".a\"/><site site=\"ps" << k
        << ".b\"/></spatial>";
    }
    o << "</tendon>";
  }
  return o.str();
}

// MuJoCo's XML parser (tinyxml2) refuses elements nested deeper than 100,
// which a 100-link chain is: bodies deeper than this in one file go to an
// included file of their own (the includes are merged after parsing).
constexpr int kDepthPerFile = 40;

struct MjcfWriter {
  const Model& m;
  std::vector<std::pair<std::string, std::string>> files;  // (name, text); [0] is the main file
  std::vector<std::vector<MjSite>> body_sites;              // mjSites(m)

  void body(std::ostream& o, int i, int depth) {
    if (depth == kDepthPerFile) {  // continue in a file of its own
      const std::string name = "part" + std::to_string(files.size()) + ".xml";
      files.emplace_back(name, "");
      const size_t slot = files.size() - 1;
      std::ostringstream part;
      part << "<mujoco>";
      body(part, i, 0);
      part << "</mujoco>";
      files[slot].second = part.str();
      o << "<include file=\"" << name << "\"/>";
      return;
    }
    const Body& b = m.bodies[i];
    const Vec3 a = b.joint.in_parent;  // parent CM -> joint point; the body's CM is that point minus c
    o << "<body name=\"" << b.name << "\" pos=\"" << vec(a - b.joint.in_body) << "\">" << inertial(b);
    joints(o, b);
    sites(o, body_sites[i + 1]);
    for (int c : b.children) body(o, c, depth + 1);
    o << "</body>";
  }
};

}  // namespace

std::vector<std::pair<std::string, std::string>> toMjcf(const Model& m) {
  MjcfWriter w{m, {{"scene.xml", ""}}, mjSites(m)};
  std::ostringstream o;
  // Constraints only where loops close (MuJoCo's equalities, soft at its default solref and solimp); never contacts.
  const char* flags = m.loops.empty() && m.limited.empty() ? "<flag contact=\"disable\" constraint=\"disable\"/>" : "<flag contact=\"disable\"/>";
  o << "<mujoco model=\"" << m.name << "\"><compiler angle=\"radian\" inertiafromgeom=\"false\"/>"
    << "<option gravity=\"" << vec(m.gravity) << "\">" << flags << "</option>"
    << "<worldbody>";
  sites(o, w.body_sites[0]);
  for (int i = 0; i < m.n(); ++i)
    if (m.bodies[i].parent < 0) w.body(o, i, 0);
  o << "</worldbody>" << mechanismXml(m) << "</mujoco>";
  w.files[0].second = o.str();
  return w.files;
}

namespace {

// The root link freed: a massless world link and a floating joint to the
// root, which MuJoCo reads as its free joint (the world link is static and fused).
void freeRoot(TiXmlElement& robot, const std::string& joint) {
  std::set<std::string> children;
  for (TiXmlElement* j = robot.FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
    if (const TiXmlElement* c = j->FirstChildElement("child"); c && c->Attribute("link")) children.insert(c->Attribute("link"));
  std::string root;
  for (TiXmlElement* l = robot.FirstChildElement("link"); l && root.empty(); l = l->NextSiblingElement("link"))
    if (l->Attribute("name") && !children.count(l->Attribute("name"))) root = l->Attribute("name");
  if (root == "world") {  // MuJoCo reads a link named world as its world body: rename it
    root = "em_root";
    for (TiXmlElement* l = robot.FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
      if (l->Attribute("name") && std::string(l->Attribute("name")) == "world") l->SetAttribute("name", root);
    for (TiXmlElement* j = robot.FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
      for (const char* end : {"parent", "child"})
        if (TiXmlElement* e = j->FirstChildElement(end); e && e->Attribute("link") && std::string(e->Attribute("link")) == "world")
          e->SetAttribute("link", root);
  }
  TiXmlDocument add;
  add.Parse(("<robot><link name=\"em_world\"/><joint name=\"" + joint + "\" type=\"floating\"><parent link=\"em_world\"/>"
             "<child link=\"" + root + "\"/></joint></robot>").c_str());
  robot.InsertBeforeChild(robot.FirstChild(), *add.RootElement()->FirstChildElement("link"));
  robot.InsertEndChild(*add.RootElement()->FirstChildElement("joint"));
}

// The URDF as MuJoCo is to read it: visual and collision elements removed,
// locked joints fixed, compiler options and disabled forces in MuJoCo's
// <mujoco> extension element.
std::string urdfForMujoco(const std::string& text, const std::vector<std::string>& locked, bool balance_inertia,
                          const std::string& floating_joint) {
  TiXmlDocument doc;
  doc.Parse(text.c_str());
  try {
    removeGeometry(doc, locked);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("MuJoCo peer: ") + e.what());
  }
  TiXmlElement* robot = doc.RootElement();
  if (!floating_joint.empty()) freeRoot(*robot, floating_joint);
  TiXmlDocument ext;
  ext.Parse((std::string("<mujoco><compiler angle=\"radian\" fusestatic=\"true\" discardvisual=\"true\" balanceinertia=\"") +
             (balance_inertia ? "true" : "false") + "\"/></mujoco>").c_str());
  robot->InsertEndChild(*ext.RootElement());
  TiXmlPrinter printer;
  doc.Accept(&printer);
  return printer.CStr();
}

// MuJoCo prints its warnings and appends them to MUJOCO_LOG.TXT in the working
// directory by default: a file nobody asked for. Runs report them instead (warnings()).
void quietWarning(const char*) {}

mjModel* compile(const std::vector<std::pair<std::string, std::string>>& files) {
  mju_user_warning = quietWarning;
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  for (const auto& [name, xml] : files) {
    if (mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(xml.size())) != 0)
      throw std::runtime_error("MuJoCo peer: cannot make the in-memory file " + name);
    std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs->filedata[vfs->nfile - 1]));
  }
  char error[1000] = "";
  mjModel* mm = mj_loadXML(files[0].first.c_str(), vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (!mm) throw std::runtime_error(std::string("MuJoCo: ") + error);
  return mm;
}

}  // namespace

struct MujocoSystem::Impl {
  mjModel* mm = nullptr;
  mjData* d = nullptr;
  std::vector<int> qadr, dof;  // MuJoCo qpos index of in-house q[i] (nq), dof index of u[i] (nu)
  std::vector<double> qoff;    // qpos = q + qoff: a free joint's rest place (nq)
  // A rotation MuJoCo reads in its child's frame (ball, free): in-house
  // quaternion at q_at, its angular speeds at u_at; u_mj = R^T u (R as of setState).
  struct Turned {
    int q_at, u_at;
    Mat3 R = Mat3::Identity();
    Vec4 rest = Vec4(1, 0, 0, 0);  ///< MuJoCo's body orientation at our zero rotation (a URDF free joint's frame)
  };
  std::vector<Turned> turned;
  std::vector<int> body;       // MuJoCo body of each in-house body (internal order)
  std::vector<std::pair<int, double>> drives;  // (MuJoCo dof, constant force) of the scene's joint.torque
  Eigen::VectorXd v;           // setState's scratch: the speeds turned into MuJoCo's frames (sized once)
  ~Impl() {
    if (d) mj_deleteData(d);
    if (mm) mj_deleteModel(mm);
  }

  // Map MuJoCo joint `jid` onto in-house body b's coordinates from q offset
  // iq and speed offset iu on; returns how many (q, u) it took.
  std::pair<int, int> take(int jid, int iq, int iu) {
    const int qa = mm->jnt_qposadr[jid], da = mm->jnt_dofadr[jid];
    int nq = 1, nv = 1;
    switch (mm->jnt_type[jid]) {
      case mjJNT_FREE: nq = 7; nv = 6; break;
      case mjJNT_BALL: nq = 4; nv = 3; break;
      default: break;
    }
    for (int k = 0; k < nq; ++k) qadr.push_back(qa + k);
    for (int k = 0; k < nv; ++k) dof.push_back(da + k);
    qoff.resize(qadr.size(), 0.0);
    if (nv == 6) turned.push_back({iq + 3, iu + 3});
    if (nv == 3) turned.push_back({iq, iu});
    return {nq, nv};
  }

  // The drives as qfrc_applied (mj_resetData clears it).
  void applyDrives() {
    for (const auto& [at, tau] : drives) d->qfrc_applied[at] = tau;
  }

  // u_mj = G^T u, and G x back: the turned speeds' blocks.
  void toInhouse(Eigen::Ref<Eigen::VectorXd> x) const {
    for (const Turned& t : turned) x.segment<3>(t.u_at) = t.R * x.segment<3>(t.u_at);
  }
};

namespace {
// MuJoCo's joint types as scenes name them (for one-line mismatches).
const char* mjTypeName(int t) {
  switch (t) {
    case mjJNT_FREE: return "free";
    case mjJNT_BALL: return "ball";
    case mjJNT_SLIDE: return "slide";
    default: return "hinge";
  }
}
// The MuJoCo joint type a URDF-read body's kind becomes (its mapping's from_urdf).
const char* mjTypeOfUrdf(const Joint& j) {
  if (const char* t = mjJoints(j).from_urdf) return t;
  throw std::runtime_error(std::string("MuJoCo peer: its reading of a URDF ") + jointTypeName(j.type) +
                           " joint is not matched to ours");
}
}  // namespace

MujocoSystem::MujocoSystem(const Model& m) : impl_(std::make_unique<Impl>()) {
  Impl& I = *impl_;
  I.mm = compile(toMjcf(m));
  I.d = mj_makeData(I.mm);
  for (const Body& b : m.bodies) {
    const int id = mj_name2id(I.mm, mjOBJ_BODY, b.name.c_str());
    I.body.push_back(id);
    int iq = b.iq, iu = b.iu;
    for (int j = I.mm->body_jntadr[id]; j < I.mm->body_jntadr[id] + I.mm->body_jntnum[id]; ++j) {
      const auto [nq, nv] = I.take(j, iq, iu);
      iq += nq;
      iu += nv;
    }
  }
  // Both anchors of every connect as the scene gives them (its compiler computed body 2's at qpos0).
  const std::vector<MjConnect> connects = mjConnects(m);
  for (size_t k = 0; k < connects.size(); ++k)
    for (int i = 0; i < 3; ++i) {
      I.mm->eq_data[mjNEQDATA * k + i] = connects[k].pa[i];
      I.mm->eq_data[mjNEQDATA * k + 3 + i] = connects[k].pb[i];
    }
  // Drives on joints whose speeds MuJoCo reads as ours (mujocoMechanismRefusal refuses ball and free joints'):
  for (const Body& b : m.bodies)
    for (int k = 0; k < b.joint.torque.size(); ++k) I.drives.push_back({I.dof[b.iu + k], b.joint.torque[k]});
  I.applyDrives();
}

MujocoSystem::MujocoSystem(const Model& m, const std::string& urdf_text, const std::vector<std::string>& joints,
                       const std::vector<std::string>& locked, bool balance_inertia, const std::string& floating_joint)
    : impl_(std::make_unique<Impl>()) {
  Impl& I = *impl_;
  I.mm = compile({{"robot.urdf", urdfForMujoco(urdf_text, locked, balance_inertia, floating_joint)}});
  I.mm->opt.disableflags |= mjDSBL_CONSTRAINT | mjDSBL_PASSIVE | mjDSBL_CONTACT;
  I.d = mj_makeData(I.mm);
  if (I.mm->nv != m.nu)
    throw std::runtime_error("MuJoCo peer: MuJoCo has " + std::to_string(I.mm->nv) + " speeds, the scene " +
                             std::to_string(m.nu));
  for (const Body& b : m.bodies) {
    const std::string& name = joints.at(b.file_index);
    const int id = mj_name2id(I.mm, mjOBJ_JOINT, name.c_str());
    const char* want = mjTypeOfUrdf(b.joint);
    if (id < 0 || std::string(mjTypeName(I.mm->jnt_type[id])) != want)
      throw std::runtime_error("MuJoCo peer: no " + std::string(want) + " joint named '" + name + "' in MuJoCo's model");
    I.body.push_back(I.mm->jnt_bodyid[id]);
    I.take(id, b.iq, b.iu);
    if (b.joint.type == JointType::Free) {  // MuJoCo's free qpos is the pose in the world, ours from the rest pose
      const int body = I.mm->jnt_bodyid[id];
      for (int k = 0; k < 3; ++k) I.qoff[I.qoff.size() - 7 + k] = I.mm->body_pos[3 * body + k];
      I.turned.back().rest = Vec4(I.mm->body_quat + 4 * body);
    }
  }
}

MujocoSystem::~MujocoSystem() = default;

void MujocoSystem::setState(const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  Impl& I = *impl_;
  for (size_t i = 0; i < I.qadr.size(); ++i) I.d->qpos[I.qadr[i]] = q[i] + I.qoff[i];
  Eigen::VectorXd& v = I.v;
  v = u;
  for (Impl::Turned& t : I.turned) {  // MuJoCo's orientation q (x) rest, its w in that frame
    const Vec4 quat = quatMul(q.segment<4>(t.q_at), t.rest);
    for (int k = 0; k < 4; ++k) I.d->qpos[I.qadr[t.q_at + k]] = quat[k];
    t.R = quatToMatrix(quat);
    v.segment<3>(t.u_at) = t.R.transpose() * v.segment<3>(t.u_at);
  }
  for (size_t i = 0; i < I.dof.size(); ++i) I.d->qvel[I.dof[i]] = v[i];
}

void MujocoSystem::forward() { mj_forward(impl_->mm, impl_->d); }

Eigen::MatrixXd MujocoSystem::massMatrix() const {
  const int nv = impl_->mm->nv;
  std::vector<mjtNum> M(nv * nv);
  mj_fullM(impl_->mm, M.data(), impl_->d->qM);
  const std::vector<int>& dof = impl_->dof;
  Eigen::MatrixXd A(nv, nv);
  for (int i = 0; i < nv; ++i)
    for (int j = 0; j < nv; ++j) A(i, j) = M[dof[i] * nv + dof[j]];
  for (const Impl::Turned& t : impl_->turned) {  // A = G A_mj G^T
    A.middleRows<3>(t.u_at) = (t.R * A.middleRows<3>(t.u_at)).eval();
    A.middleCols<3>(t.u_at) = (A.middleCols<3>(t.u_at) * t.R.transpose()).eval();
  }
  return A;
}

std::vector<CompiledMass> MujocoSystem::compiledMass() {
  const mjModel* mm = impl_->mm;
  mjData* d = impl_->d;
  mju_copy(d->qpos, mm->qpos0, mm->nq);  // the zero configuration (a quaternion's is 1 0 0 0)
  mj_kinematics(mm, d);
  std::vector<CompiledMass> out;
  for (int b : impl_->body) {
    Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->ximat + 9 * b);  // principal axes in the world
    const Vec3 I(mm->body_inertia + 3 * b);
    out.push_back({mm->body_mass[b], Vec3(d->xipos + 3 * b), R * I.asDiagonal() * R.transpose()});
  }
  return out;
}

Eigen::VectorXd MujocoSystem::acceleration() const {
  Eigen::VectorXd a(impl_->mm->nv);
  acceleration(a.data());
  return a;
}

void MujocoSystem::acceleration(double* udot) const {
  Eigen::Map<Eigen::VectorXd> a(udot, static_cast<Eigen::Index>(impl_->dof.size()));
  for (Eigen::Index i = 0; i < a.size(); ++i) a[i] = impl_->d->qacc[impl_->dof[i]];
  impl_->toInhouse(a);  // u' = G u_mj' (G' u_mj = w x w = 0)
}

Eigen::VectorXd MujocoSystem::rhs() const {
  Eigen::VectorXd B(impl_->mm->nv);
  // MuJoCo's passive forces are the scene's springs and dampers (none from a URDF: disabled).
  // Drives are qfrc_applied; a point spring's force is in qfrc_passive (its tendon's).
  for (int i = 0; i < B.size(); ++i)
    B[i] = impl_->d->qfrc_passive[impl_->dof[i]] + impl_->d->qfrc_applied[impl_->dof[i]] - impl_->d->qfrc_bias[impl_->dof[i]];
  impl_->toInhouse(B);  // B = G B_mj
  return B;
}

}  // namespace em

namespace em {

void MujocoSystem::configure(int scheme, double dt, bool energies) {
  mjModel* mm = impl_->mm;
  mm->opt.integrator = scheme;
  mm->opt.timestep = dt;
  computeEnergies(energies);
  mj_resetData(mm, impl_->d);
  impl_->applyDrives();
}

void MujocoSystem::computeEnergies(bool on) {
  mjModel* mm = impl_->mm;
  if (on) mm->opt.enableflags |= mjENBL_ENERGY;
  else mm->opt.enableflags &= ~mjENBL_ENERGY;
}

void MujocoSystem::step() { mj_step(impl_->mm, impl_->d); }

void MujocoSystem::getState(Eigen::VectorXd& q, Eigen::VectorXd& u) const {
  const Impl& I = *impl_;
  q.resize(static_cast<Eigen::Index>(I.qadr.size()));
  u.resize(static_cast<Eigen::Index>(I.dof.size()));
  for (size_t i = 0; i < I.qadr.size(); ++i) q[i] = I.d->qpos[I.qadr[i]] - I.qoff[i];
  for (size_t i = 0; i < I.dof.size(); ++i) u[i] = I.d->qvel[I.dof[i]];
  for (const Impl::Turned& t : I.turned) {  // ours = MuJoCo's (x) rest^-1; w back to the parent's frame
    const Vec4 quat = q.segment<4>(t.q_at);
    const Vec4 inv(t.rest[0], -t.rest[1], -t.rest[2], -t.rest[3]);
    q.segment<4>(t.q_at) = quatMul(quat, inv);
    u.segment<3>(t.u_at) = quatToMatrix(quat) * u.segment<3>(t.u_at);
  }
}

std::vector<Pose> MujocoSystem::poses() const {
  const Impl& I = *impl_;
  std::vector<Pose> out(I.body.size());
  for (size_t i = 0; i < I.body.size(); ++i) {  // the MJCF body frame is the in-house one, at the CM
    const int b = I.body[i];
    out[i].p = Vec3(I.d->xipos + 3 * b);
    out[i].quat = Vec4(I.d->xquat + 4 * b);
  }
  return out;
}

double MujocoSystem::kineticEnergy() const { return impl_->d->energy[1]; }
void MujocoSystem::soften(const double solref[2], const double solimp[3]) {
  mjModel* mm = impl_->mm;
  for (int e = 0; e < mm->neq; ++e) {
    for (int k = 0; k < 2; ++k) mm->eq_solref[mjNREF * e + k] = solref[k];
    for (int k = 0; k < 3; ++k) mm->eq_solimp[mjNIMP * e + k] = solimp[k];  // midpoint and power kept (0.5, 2)
  }
}

double MujocoSystem::potentialEnergy() const { return impl_->d->energy[0]; }

void MujocoSystem::softenLimits(const double solref[2]) {
  mjModel* mm = impl_->mm;
  for (int j = 0; j < mm->njnt; ++j)
    if (mm->jnt_limited[j])
      for (int k = 0; k < 2; ++k) mm->jnt_solref[mjNREF * j + k] = solref[k];
}

void MujocoSystem::applyControl(const Eigen::VectorXd& tau) {
  auto& I = *impl_;
  for (int at : I.dof) I.d->qfrc_applied[at] = 0;
  I.applyDrives();
  for (Eigen::Index i = 0; i < tau.size(); ++i) I.d->qfrc_applied[I.dof[static_cast<size_t>(i)]] += tau[i];
}

double MujocoSystem::dissipationRate() const {
  const mjModel* mm = impl_->mm;
  double P = 0;
  for (int i = 0; i < mm->nv; ++i) P += mm->dof_damping[i] * impl_->d->qvel[i] * impl_->d->qvel[i];
  for (const auto& [at, tau] : impl_->drives) P -= tau * impl_->d->qvel[at];  // a drive's power counts negative
  for (int t = 0; t < mm->ntendon; ++t)  // a point damper's (its spatial tendon's damping): c l'^2
    P += mm->tendon_damping[t] * impl_->d->ten_velocity[t] * impl_->d->ten_velocity[t];
  return P;
}

double MujocoSystem::dissipationRateDerivative() const {
  const mjModel* mm = impl_->mm;
  double dP = 0;
  for (int i = 0; i < mm->nv; ++i) dP += 2 * mm->dof_damping[i] * impl_->d->qvel[i] * impl_->d->qacc[i];
  for (const auto& [at, tau] : impl_->drives) dP -= tau * impl_->d->qacc[at];
  // A point damper's 2 c l' l'', l'' taken as J qacc: MuJoCo gives no rate of
  // the tendon's Jacobian, and the omitted J' qvel leaves W_diss's end
  // correction second order where point dampers are (fourth elsewhere).
  for (int t = 0; t < mm->ntendon; ++t) {
    double ldd = 0;
    for (int i = 0; i < mm->nv; ++i) ldd += impl_->d->ten_J[t * mm->nv + i] * impl_->d->qacc[i];
    dP += 2 * mm->tendon_damping[t] * impl_->d->ten_velocity[t] * ldd;
  }
  return dP;
}

std::string MujocoSystem::warnings() const {
  std::string out;
  for (int i = 0; i < mjNWARNING; ++i)
    if (impl_->d->warning[i].number > 0)
      out += (out.empty() ? "" : "; ") + std::string(mju_warningText(i, impl_->d->warning[i].lastinfo));
  return out;
}

}  // namespace em
