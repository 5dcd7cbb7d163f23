#pragma once
// Momenta of a state and their drift over a run: the invariants of a free
// system in zero gravity (tests of sliding joints, in-house and Simbody).
#include <algorithm>
#include <utility>

#include "solver/formation.hpp"
#include "solver/trajectory.hpp"

namespace em::test {

// Linear momentum, angular momentum about the world origin and CM of a state.  // (internal q, u)
struct Momenta {
  Vec3 p = Vec3::Zero(), H = Vec3::Zero(), cm = Vec3::Zero();
  double mass = 0;
};
inline Momenta momenta(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  Workspace ws(m);
  formKinematics(m, q.data(), u.data(), ws);
  Momenta s;
  for (int i = 0; i < m.n(); ++i) {
    const double mi = m.bodies[i].mass;
    s.p += mi * ws.v[i];
    s.H += ws.r[i].cross(mi * ws.v[i]) + ws.J_w[i] * ws.omega[i];
    s.cm += mi * ws.r[i];
    s.mass += mi;
  }
  s.cm /= s.mass;
  return s;
}

// A trajectory's sample k in internal order.
inline void internalState(const Model& m, const Trajectory& tr, size_t k, Eigen::VectorXd& q, Eigen::VectorXd& u) {
  const std::vector<int> pq = m.qFilePermutation(), pu = m.uFilePermutation();
  q.resize(m.nq);
  u.resize(m.nu);
  for (int i = 0; i < m.nq; ++i) q[pq[i]] = tr.q[k][i];
  for (int i = 0; i < m.nu; ++i) u[pu[i]] = tr.u[k][i];
}

// Largest drift of p and H over a run, relative to their size at t = 0.
inline std::pair<double, double> momentumDrift(const Model& m, const Trajectory& tr) {
  Eigen::VectorXd q, u;
  internalState(m, tr, 0, q, u);
  const Momenta m0 = momenta(m, q, u);
  double dp = 0, dH = 0;
  for (size_t k = 0; k < tr.size(); ++k) {
    internalState(m, tr, k, q, u);
    const Momenta mk = momenta(m, q, u);
    dp = std::max(dp, (mk.p - m0.p).norm() / m0.p.norm());
    dH = std::max(dH, (mk.H - m0.H).norm() / m0.H.norm());
  }
  return {dp, dH};
}

}  // namespace em::test
