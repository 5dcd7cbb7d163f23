#include "compare/momenta.hpp"

#include <algorithm>

#include "solver/formation.hpp"

namespace em {

namespace {

struct Momenta {
  Vec3 p = Vec3::Zero(), Hc = Vec3::Zero();  // linear; angular about the CM
};

// The momenta at sample k (source-order q, u permuted to the internal order by pq, pu).
Momenta momentaAt(const Model& m, const Trajectory& tr, size_t k, const std::vector<int>& pq, const std::vector<int>& pu,
                  Eigen::VectorXd& q, Eigen::VectorXd& u, Workspace& ws) {
  for (int i = 0; i < m.nq; ++i) q[pq[i]] = tr.q[k][i];
  for (int i = 0; i < m.nu; ++i) u[pu[i]] = tr.u[k][i];
  formKinematics(m, q.data(), u.data(), ws);
  double mass = 0;
  Vec3 c = Vec3::Zero();
  Momenta s;
  for (int i = 0; i < m.n(); ++i) {
    mass += m.bodies[i].mass;
    c += m.bodies[i].mass * ws.r[i];
    s.p += m.bodies[i].mass * ws.v[i];
  }
  c /= mass;
  for (int i = 0; i < m.n(); ++i) s.Hc += (ws.r[i] - c).cross(m.bodies[i].mass * ws.v[i]) + ws.J_w[i] * ws.omega[i];
  return s;
}

double totalMass(const Model& m) {
  double mass = 0;
  for (const Body& b : m.bodies) mass += b.mass;
  return mass;
}

}  // namespace

bool freeSystem(const Model& m) {
  for (const Body& b : m.bodies)
    if (b.parent < 0 && (b.joint.type != JointType::Free || b.joint.has_spring)) return false;
  return m.n() > 0;
}

std::optional<MomentumDrift> momentumDrift(const Model& m, const Trajectory& tr) {
  if (!freeSystem(m) || tr.size() == 0) return std::nullopt;
  const std::vector<int> pq = m.qFilePermutation(), pu = m.uFilePermutation();
  Eigen::VectorXd q(m.nq), u(m.nu);
  Workspace ws(m);
  const Momenta s0 = momentaAt(m, tr, 0, pq, pu, q, u, ws);
  const Vec3 weight = totalMass(m) * m.gravity;
  double dp = 0, dH = 0;
  for (size_t k = 0; k < tr.size(); ++k) {
    const Momenta s = momentaAt(m, tr, k, pq, pu, q, u, ws);
    dp = std::max(dp, (s.p - weight * (tr.t[k] - tr.t[0]) - s0.p).norm());
    dH = std::max(dH, (s.Hc - s0.Hc).norm());
  }
  MomentumDrift d;
  if (s0.p.norm() > 0) d.p = dp / s0.p.norm();
  if (s0.Hc.norm() > 0) d.H = dH / s0.Hc.norm();
  return d;
}

}  // namespace em
