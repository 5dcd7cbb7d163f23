#include "reference/mujoco_peer.hpp"

#include <cstdio>
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

void hinge(std::ostream& o, const Body& b, int k, const Vec3& axis) {
  o << "<joint name=\"" << b.name << ".q" << k << "\" type=\"hinge\" pos=\"" << vec(b.joint.in_body) << "\" axis=\""
    << vec(axis) << "\"/>";
}

// MuJoCo's XML parser (tinyxml2) refuses elements nested deeper than 100,
// which a 100-link chain is: bodies deeper than this in one file go to an
// included file of their own (the includes are merged after parsing).
constexpr int kDepthPerFile = 40;

struct MjcfWriter {
  const Model& m;
  std::vector<std::pair<std::string, std::string>> files;  // (name, text); [0] is the main file

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
    switch (b.joint.type) {
      case JointType::Revolute: hinge(o, b, 0, b.joint.axis[0]); break;
      case JointType::Universal: hinge(o, b, 0, b.joint.axis[0]); hinge(o, b, 1, b.joint.axis[1]); break;
      case JointType::Gimbal:
        for (int k = 0; k < 3; ++k) hinge(o, b, k, Vec3::Unit(k));
        break;
      case JointType::Ball: throw std::runtime_error("MuJoCo peer: ball joints are not mapped (body '" + b.name + "')");
    }
    for (int c : b.children) body(o, c, depth + 1);
    o << "</body>";
  }
};

}  // namespace

std::vector<std::pair<std::string, std::string>> toMjcf(const Model& m) {
  MjcfWriter w{m, {{"scene.xml", ""}}};
  std::ostringstream o;
  o << "<mujoco model=\"" << m.name << "\"><compiler angle=\"radian\" inertiafromgeom=\"false\"/>"
    << "<option gravity=\"" << vec(m.gravity) << "\"><flag contact=\"disable\" constraint=\"disable\" passive=\"disable\"/></option>"
    << "<worldbody>";
  for (int i = 0; i < m.n(); ++i)
    if (m.bodies[i].parent < 0) w.body(o, i, 0);
  o << "</worldbody></mujoco>";
  w.files[0].second = o.str();
  return w.files;
}

namespace {

// The URDF as MuJoCo is to read it: visual and collision elements removed,
// locked joints fixed, compiler options and disabled forces in MuJoCo's
// <mujoco> extension element.
std::string urdfForMujoco(const std::string& text, const std::vector<std::string>& locked, bool balance_inertia) {
  TiXmlDocument doc;
  doc.Parse(text.c_str());
  TiXmlElement* robot = doc.RootElement();
  if (!robot) throw std::runtime_error("MuJoCo peer: the URDF does not parse as XML");
  for (TiXmlElement* link = robot->FirstChildElement("link"); link; link = link->NextSiblingElement("link"))
    for (const char* tag : {"visual", "collision"})
      while (TiXmlElement* e = link->FirstChildElement(tag)) link->RemoveChild(e);
  for (TiXmlElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
    for (const std::string& name : locked)
      if (j->Attribute("name") && name == j->Attribute("name")) j->SetAttribute("type", "fixed");
  TiXmlDocument ext;
  ext.Parse((std::string("<mujoco><compiler angle=\"radian\" fusestatic=\"true\" discardvisual=\"true\" balanceinertia=\"") +
             (balance_inertia ? "true" : "false") + "\"/></mujoco>").c_str());
  robot->InsertEndChild(*ext.RootElement());
  TiXmlPrinter printer;
  doc.Accept(&printer);
  return printer.CStr();
}

mjModel* compile(const std::vector<std::pair<std::string, std::string>>& files) {
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

struct MujocoPeer::Impl {
  mjModel* mm = nullptr;
  mjData* d = nullptr;
  std::vector<int> qadr, dof;  // MuJoCo qpos and dof address of in-house q[i] = u[i] (hinges only)
  ~Impl() {
    if (d) mj_deleteData(d);
    if (mm) mj_deleteModel(mm);
  }
};

MujocoPeer::MujocoPeer(const Model& m) : impl_(std::make_unique<Impl>()) {
  impl_->mm = compile(toMjcf(m));
  impl_->d = mj_makeData(impl_->mm);
  for (const Body& b : m.bodies) {
    const int id = mj_name2id(impl_->mm, mjOBJ_BODY, b.name.c_str());
    for (int k = 0; k < b.nu(); ++k) {
      impl_->dof.push_back(impl_->mm->body_dofadr[id] + k);
      impl_->qadr.push_back(impl_->mm->body_dofadr[id] + k);  // hinges only: qpos index = dof index
    }
  }
}

MujocoPeer::MujocoPeer(const Model& m, const std::string& urdf_text, const std::vector<std::string>& joints,
                       const std::vector<std::string>& locked, bool balance_inertia)
    : impl_(std::make_unique<Impl>()) {
  impl_->mm = compile({{"robot.urdf", urdfForMujoco(urdf_text, locked, balance_inertia)}});
  impl_->mm->opt.disableflags |= mjDSBL_CONSTRAINT | mjDSBL_PASSIVE | mjDSBL_CONTACT;
  impl_->d = mj_makeData(impl_->mm);
  if (impl_->mm->nv != m.nu)
    throw std::runtime_error("MuJoCo peer: MuJoCo has " + std::to_string(impl_->mm->nv) + " speeds, the scene " +
                             std::to_string(m.nu));
  for (const Body& b : m.bodies) {
    const std::string& name = joints.at(b.file_index);
    const int id = mj_name2id(impl_->mm, mjOBJ_JOINT, name.c_str());
    if (id < 0 || impl_->mm->jnt_type[id] != mjJNT_HINGE)
      throw std::runtime_error("MuJoCo peer: no hinge named '" + name + "' in MuJoCo's model");
    impl_->qadr.push_back(impl_->mm->jnt_qposadr[id]);
    impl_->dof.push_back(impl_->mm->jnt_dofadr[id]);
  }
}

MujocoPeer::~MujocoPeer() = default;

void MujocoPeer::setState(const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  for (size_t i = 0; i < impl_->dof.size(); ++i) {
    impl_->d->qpos[impl_->qadr[i]] = q[i];
    impl_->d->qvel[impl_->dof[i]] = u[i];
  }
}

void MujocoPeer::forward() { mj_forward(impl_->mm, impl_->d); }

Eigen::MatrixXd MujocoPeer::massMatrix() const {
  const int nv = impl_->mm->nv;
  std::vector<mjtNum> M(nv * nv);
  mj_fullM(impl_->mm, M.data(), impl_->d->qM);
  const std::vector<int>& dof = impl_->dof;
  Eigen::MatrixXd A(nv, nv);
  for (int i = 0; i < nv; ++i)
    for (int j = 0; j < nv; ++j) A(i, j) = M[dof[i] * nv + dof[j]];
  return A;
}

std::vector<CompiledMass> MujocoPeer::compiledMass() {
  const mjModel* mm = impl_->mm;
  mjData* d = impl_->d;
  mju_zero(d->qpos, mm->nq);  // hinges only: zero is the zero configuration
  mj_kinematics(mm, d);
  std::vector<CompiledMass> out;
  for (int dof : impl_->dof) {
    const int b = mm->dof_bodyid[dof];
    Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> R(d->ximat + 9 * b);  // principal axes in the world
    const Vec3 I(mm->body_inertia + 3 * b);
    out.push_back({mm->body_mass[b], Vec3(d->xipos + 3 * b), R * I.asDiagonal() * R.transpose()});
  }
  return out;
}

Eigen::VectorXd MujocoPeer::acceleration() const {
  Eigen::VectorXd a(impl_->mm->nv);
  for (int i = 0; i < a.size(); ++i) a[i] = impl_->d->qacc[impl_->dof[i]];
  return a;
}

Eigen::VectorXd MujocoPeer::rhs() const {
  Eigen::VectorXd B(impl_->mm->nv);
  for (int i = 0; i < B.size(); ++i) B[i] = -impl_->d->qfrc_bias[impl_->dof[i]];
  return B;
}

}  // namespace em
