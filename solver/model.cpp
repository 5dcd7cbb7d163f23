#include "solver/model.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace em {

const char* jointTypeName(JointType t) {
  switch (t) {
    case JointType::Revolute: return "revolute";
    case JointType::Universal: return "universal";
    case JointType::Gimbal: return "gimbal";
    case JointType::Ball: return "ball";
  }
  return "?";
}

int jointNu(JointType t) {
  switch (t) {
    case JointType::Revolute: return 1;
    case JointType::Universal: return 2;
    default: return 3;
  }
}

int jointNq(JointType t) { return t == JointType::Ball ? 4 : jointNu(t); }

namespace {

std::string bodyPath(int file_index, const char* key) {
  return "bodies[" + std::to_string(file_index) + "]." + key;
}

// Depth-first, children in file order: parents get lower numbers (regular numbering).
void numberSubtree(int f, const std::vector<std::vector<int>>& kids, std::vector<int>& order) {
  order.push_back(f);
  for (int k : kids[f]) numberSubtree(k, kids, order);
}

}  // namespace

Model buildModel(const SceneSpec& spec) {
  const int n = static_cast<int>(spec.bodies.size());
  if (n == 0) throw SceneError("bodies", "empty body list");
  std::map<std::string, int> by_name;
  for (int f = 0; f < n; ++f) {
    const auto& name = spec.bodies[f].name;
    if (name.empty()) throw SceneError(bodyPath(f, "name"), "empty name");
    if (name == "ground") throw SceneError(bodyPath(f, "name"), "'ground' is reserved");
    if (!by_name.emplace(name, f).second)
      throw SceneError(bodyPath(f, "name"), "duplicate name '" + name + "' (first at bodies[" +
                                                std::to_string(by_name[name]) + "])");
  }
  std::vector<int> parent_file(n);
  std::vector<std::vector<int>> kids(n);
  std::vector<int> roots;
  for (int f = 0; f < n; ++f) {
    const auto& p = spec.bodies[f].parent;
    if (p == "ground") { parent_file[f] = -1; roots.push_back(f); continue; }
    auto it = by_name.find(p);
    if (it == by_name.end()) throw SceneError(bodyPath(f, "parent"), "unknown parent '" + p + "'");
    if (it->second == f) throw SceneError(bodyPath(f, "parent"), "a body cannot be its own parent");
    parent_file[f] = it->second;
    kids[it->second].push_back(f);
  }
  // Every body must reach the ground; walking up more than n steps means a cycle.
  for (int f = 0; f < n; ++f) {
    int x = f, steps = 0;
    while (x >= 0 && steps <= n) { x = parent_file[x]; ++steps; }
    if (x >= 0)
      throw SceneError(bodyPath(f, "parent"), "cycle: '" + spec.bodies[f].name +
                                                  "' does not reach the ground");
  }
  std::vector<int> order;
  for (int r : roots) numberSubtree(r, kids, order);

  Model m;
  m.name = spec.name;
  m.gravity = spec.gravity;
  m.has_gravity = spec.gravity.squaredNorm() > 0;
  m.t_end = spec.t_end;
  m.output_dt = spec.output_dt;
  m.file_to_internal.assign(n, -1);
  for (int i = 0; i < n; ++i) m.file_to_internal[order[i]] = i;
  m.bodies.resize(n);
  for (int i = 0; i < n; ++i) {
    const BodySpec& s = spec.bodies[order[i]];
    Body& b = m.bodies[i];
    b.name = s.name;
    b.parent = parent_file[order[i]] < 0 ? -1 : m.file_to_internal[parent_file[order[i]]];
    b.mass = s.mass;
    b.J = s.inertia;
    b.joint = s.joint;
    b.file_index = order[i];
    b.iq = m.nq;
    b.iu = m.nu;
    m.nq += b.nq();
    m.nu += b.nu();
    m.has_springs = m.has_springs || b.joint.has_spring;
    if (b.parent >= 0) m.bodies[b.parent].children.push_back(i);
  }
  int fq = 0, fu = 0;
  for (int f = 0; f < n; ++f) {
    Body& b = m.bodies[m.file_to_internal[f]];
    b.file_iq = fq;
    b.file_iu = fu;
    fq += b.nq();
    fu += b.nu();
  }
  // T(j,i) = 1 when joint j lies on the path from the ground to body i (docs/theory.md §2).
  m.T = Eigen::MatrixXi::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = i; j >= 0; j = m.bodies[j].parent) m.T(j, i) = 1;
  return m;
}

Eigen::VectorXd Model::q0() const {
  Eigen::VectorXd q(nq);
  for (const Body& b : bodies) q.segment(b.iq, b.nq()) = b.joint.q0;
  return q;
}

Eigen::VectorXd Model::u0() const {
  Eigen::VectorXd u(nu);
  for (const Body& b : bodies) u.segment(b.iu, b.nu()) = b.joint.u0;
  return u;
}

namespace {
// Copy each body's block of q (or u) between internal and file order.
void permute(const Model& m, bool speeds, bool to_file, const Eigen::VectorXd& in, Eigen::VectorXd& out) {
  out.resize(speeds ? m.nu : m.nq);
  for (const Body& b : m.bodies) {
    const int k = speeds ? b.nu() : b.nq();
    const int internal = speeds ? b.iu : b.iq, file = speeds ? b.file_iu : b.file_iq;
    out.segment(to_file ? file : internal, k) = in.segment(to_file ? internal : file, k);
  }
}
}  // namespace

void Model::qFromFile(const Eigen::VectorXd& qf, Eigen::VectorXd& q) const { permute(*this, false, false, qf, q); }
void Model::qToFile(const Eigen::VectorXd& q, Eigen::VectorXd& qf) const { permute(*this, false, true, q, qf); }
void Model::uFromFile(const Eigen::VectorXd& uf, Eigen::VectorXd& u) const { permute(*this, true, false, uf, u); }
void Model::uToFile(const Eigen::VectorXd& u, Eigen::VectorXd& uf) const { permute(*this, true, true, u, uf); }

std::vector<int> Model::uFilePermutation() const {
  std::vector<int> p(nu);
  for (const Body& b : bodies)
    for (int k = 0; k < b.nu(); ++k) p[b.file_iu + k] = b.iu + k;
  return p;
}

namespace {
std::vector<std::string> coordNames(const Model& m, bool speeds) {
  std::vector<std::string> names(speeds ? m.nu : m.nq);
  for (const Body& b : m.bodies) {
    const int k = speeds ? b.nu() : b.nq(), at = speeds ? b.file_iu : b.file_iq;
    for (int c = 0; c < k; ++c) names[at + c] = b.name + (speeds ? ".u" : ".q") + std::to_string(c);
  }
  return names;
}
}  // namespace

std::vector<std::string> Model::qNames() const { return coordNames(*this, false); }
std::vector<std::string> Model::uNames() const { return coordNames(*this, true); }

SceneSpec makeChainSpec(int n, bool ball_root) {
  // Slender rods of length 1 m, mass 1 kg (pendulum5's links), hanging from the origin.
  SceneSpec s;
  s.name = "chain" + std::to_string(n);
  const double m = 1.0, L = 1.0, r = 0.05;
  const double Ixx = m * (3 * r * r + L * L) / 12.0, Izz = m * r * r / 2.0;
  for (int i = 0; i < n; ++i) {
    BodySpec b;
    b.name = "link" + std::to_string(i + 1);
    b.parent = i == 0 ? "ground" : "link" + std::to_string(i);
    b.mass = m;
    b.inertia = Vec3(Ixx, Ixx, Izz).asDiagonal();
    b.joint.in_parent = i == 0 ? Vec3::Zero() : Vec3(0, 0, -L / 2);
    b.joint.in_body = Vec3(0, 0, L / 2);
    if (i == 0) {
      b.joint.type = ball_root ? JointType::Ball : JointType::Gimbal;
      b.joint.q0 = ball_root ? Eigen::VectorXd(Vec4(1, 0, 0, 0)) : Eigen::VectorXd(Vec3(0.6, -0.5, 0.3));
      b.joint.u0 = Vec3(0.2, -0.1, 0.3);
    } else {
      b.joint.type = JointType::Revolute;
      b.joint.axis[0] = i % 2 ? Vec3::UnitX() : Vec3::UnitY();
      b.joint.q0 = Eigen::VectorXd::Constant(1, 0.5 * std::sin(1.3 * i));
      b.joint.u0 = Eigen::VectorXd::Constant(1, 0.2 * std::cos(0.7 * i));
    }
    s.bodies.push_back(b);
  }
  return s;
}

}  // namespace em
