#include "bench/mujoco_peer.hpp"

#include <cstdio>
#include <sstream>
#include <stdexcept>

#include <mujoco/mujoco.h>

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

struct MujocoPeer::Impl {
  const Model& model;
  mjModel* mm = nullptr;
  mjData* d = nullptr;
  std::vector<int> dof;  // MuJoCo dof of in-house u[i] (= qpos index: hinges only)
  explicit Impl(const Model& m) : model(m) {}
  ~Impl() {
    if (d) mj_deleteData(d);
    if (mm) mj_deleteModel(mm);
  }
};

MujocoPeer::MujocoPeer(const Model& m) : impl_(std::make_unique<Impl>(m)) {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  for (const auto& [name, xml] : toMjcf(m)) {
    if (mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(xml.size())) != 0)
      throw std::runtime_error("MuJoCo peer: cannot make the in-memory MJCF file " + name);
    std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs->filedata[vfs->nfile - 1]));
  }
  char error[1000] = "";
  impl_->mm = mj_loadXML("scene.xml", vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (!impl_->mm) throw std::runtime_error(std::string("MuJoCo peer: ") + error);
  impl_->d = mj_makeData(impl_->mm);
  for (const Body& b : m.bodies) {
    const int id = mj_name2id(impl_->mm, mjOBJ_BODY, b.name.c_str());
    for (int k = 0; k < b.nu(); ++k) impl_->dof.push_back(impl_->mm->body_dofadr[id] + k);
  }
}

MujocoPeer::~MujocoPeer() = default;

void MujocoPeer::setState(const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  for (size_t i = 0; i < impl_->dof.size(); ++i) {
    impl_->d->qpos[impl_->dof[i]] = q[i];  // hinges only: qpos index = dof index
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

Eigen::VectorXd MujocoPeer::rhs() const {
  Eigen::VectorXd B(impl_->mm->nv);
  for (int i = 0; i < B.size(); ++i) B[i] = -impl_->d->qfrc_bias[impl_->dof[i]];
  return B;
}

}  // namespace em
