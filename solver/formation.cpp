#include "solver/formation.hpp"

#include "solver/applied_forces.hpp"

#include <limits>

#include <Eigen/Eigenvalues>


namespace em {

namespace {

// (a . b) E - b (x) a: the dyadic kernel of K (docs/theory.md §4).
inline Mat3 kernel(const Vec3& a, const Vec3& b) {
  return a.dot(b) * Mat3::Identity() - b * a.transpose();
}

}  // namespace

void formKinematics(const Model& m, const double* q, const double* u, Workspace& ws) {
  // Outward recursion over the regular numbering (parents first); docs/theory.md §3, §12.
  Axes Pj, Pdj;
  for (int i = 0; i < m.n(); ++i) {
    const Body& body = m.bodies[i];
    const int p = body.parent, nt = body.nt(), nr = body.nu() - nt;
    const Mat3 R_p = p < 0 ? Mat3::Identity() : ws.R[p];
    const Vec3 w_p = p < 0 ? Vec3::Zero() : ws.omega[p];
    const double* qi = q + body.iq;
    const double* ui = u + body.iu;
    ws.R[i] = R_p * relativeRotation(body.joint, qi);
    worldAxes(body.joint, R_p, qi, Pj);
    // Column loops, not products of dynamic size: nu <= 6, and this runs per body per evaluation.
    Vec3 w = w_p, v_rel = Vec3::Zero();
    for (int k = 0; k < nt; ++k) v_rel += Pj.col(k) * ui[k];
    for (int k = nt; k < nt + nr; ++k) w += Pj.col(k) * ui[k];
    ws.omega[i] = w;
    axisRates(body.joint, Pj, w_p, w, ui, Pdj);
    for (int k = 0; k < nt + nr; ++k) {
      ws.P.col(body.iu + k) = Pj.col(k);
      ws.Pdot.col(body.iu + k) = Pdj.col(k);
    }
    ws.J_w[i] = ws.R[i] * body.J * ws.R[i].transpose();
    ws.b[i] = -(ws.R[i] * body.joint.in_body);
    // Joint point i, and its velocity, from the parent's joint point; a
    // sliding joint moves it by x along the parent's axes at v_rel (eq. (T1)).
    const Vec3 x = nt == 0 ? Vec3::Zero() : slideOffset(body.joint, qi);
    ws.v_rel[i] = v_rel;
    Vec3 v_o = v_rel;
    if (p < 0) {
      ws.d[i].setZero();
      ws.o[i] = nt == 0 ? body.joint.in_parent : Vec3(body.joint.in_parent + x);
    } else {
      ws.d[i] = nt == 0 ? Vec3(R_p * (body.joint.in_parent - m.bodies[p].joint.in_body))
                        : Vec3(R_p * (body.joint.in_parent - m.bodies[p].joint.in_body + x));
      ws.o[i] = ws.o[p] + ws.d[i];
      v_o += ws.v[p] - w_p.cross(ws.b[p]) + w_p.cross(ws.d[i]);  // v of joint point p, then to i
    }
    ws.vo[i] = v_o;
    ws.r[i] = ws.o[i] + ws.b[i];
    ws.v[i] = v_o + ws.omega[i].cross(ws.b[i]);
  }
}

void formEnergies(const Model& m, const double* q, Workspace& ws) {
  ws.kinetic = 0;
  for (int i = 0; i < m.n(); ++i)
    ws.kinetic += 0.5 * (m.bodies[i].mass * ws.v[i].squaredNorm() + ws.omega[i].dot(ws.J_w[i] * ws.omega[i]));
  ws.potential = potentialEnergy(m, q, ws);
}

double potentialEnergy(const Model& m, const double* q, const Workspace& ws) {
  double V = 0;
  for (int i = 0; i < m.n(); ++i) {
    const Body& body = m.bodies[i];
    V -= body.mass * m.gravity.dot(ws.r[i]);
    if (!body.joint.has_spring) continue;
    const Spring& sp = body.joint.spring;
    for (int k = 0; k < body.nu(); ++k) {
      const double e = q[body.iq + k] - sp.q_rest[k];
      V += 0.5 * sp.k[k] * e * e;
    }
  }
  if (!m.point_springs.empty()) V += pointSpringPotential(m, ws);
  return V;
}

void formSubtrees(const Model& m, Workspace& ws) {
  // Bottom-up (regular numbering: children after parents), docs/theory.md §4.
  for (int k = m.n() - 1; k >= 0; --k) {
    const Body& body = m.bodies[k];
    ws.mu[k] = body.mass;
    ws.s[k] = body.mass * ws.b[k];
    // K_kk: the augmented body k's inertia about joint k.
    ws.Kd[k] = ws.J_w[k] + body.mass * kernel(ws.b[k], ws.b[k]);
    ws.S[k] = ws.s[k];
    ws.IC[k] = ws.Kd[k];
    for (int c : body.children) {
      const Vec3& d = ws.d[c];
      ws.mu[k] += ws.mu[c];
      ws.s[k] += ws.mu[c] * d;
      const Mat3 dd = ws.mu[c] * kernel(d, d);
      ws.Kd[k] += dd;
      // S_c and I_c moved from joint c to joint k (parallel axes, d = o_c - o_k).
      ws.IC[k] += ws.IC[c] + dd + kernel(d, ws.S[c]) + kernel(ws.S[c], d);
      ws.S[k] += ws.S[c] + ws.mu[c] * d;
    }
  }
}

namespace {

// Column b of A (of body k): the momentum per unit u_b of subtree(k), as an
// angular part sigma about joint point k and a linear part pi (docs/theory.md
// eq. (T2)): rotation p_b: sigma = I_k p_b, pi = p_b x S_k; slide t_b:
// sigma = S_k x t_b, pi = mu_k t_b.
struct ColumnMomentum {
  Vec3 sigma, pi;  ///< angular part about joint point k, linear part
};

template <bool kSliding>
ColumnMomentum columnMomentum(const Workspace& ws, int k, const Vec3& p_b, bool slides) {
  if (kSliding && slides) return {ws.S[k].cross(p_b), ws.mu[k] * p_b};
  return {ws.IC[k] * p_b, p_b.cross(ws.S[k])};
}

// A_ab = p_a . (sigma + r_jk x pi) for a rotation axis p_a of ancestor j,
// t_a . pi for a slide t_a (eq. (T3)), down column b.
template <bool kSliding>
void formAImpl(const Model& m, Workspace& ws) {
  // The lever r_jk = o_k - o_j is formed from the joint points, so j = k is
  // free of cancellation. Rows a <= b only, written down column b (contiguous)
  // and mirrored into row b: only the tree's pattern is touched (O(nu depth),
  // not O(nu^2)); the rest of A stays zero from the Workspace's construction.
  const int N = m.nu;
  const auto set = [&ws, N](double* A_b, int a, int b, double value) {
    if (a > b) return;  // the same body's later speed: its own column writes it
    A_b[a] = value;
    ws.A.data()[static_cast<size_t>(a) * N + b] = value;
  };
  for (int k = 0; k < m.n(); ++k) {
    const int b0 = m.body_iu[k];
    for (int b = b0; b < b0 + m.body_nu[k]; ++b) {
      const ColumnMomentum c = columnMomentum<kSliding>(ws, k, ws.P.col(b), b < b0 + m.body_nt[k]);
      double* A_b = ws.A.data() + static_cast<size_t>(b) * N;  // column b
      for (int j = k; j >= 0; j = m.body_parent[j]) {
        const int a0 = m.body_iu[j], a_rot = kSliding ? a0 + m.body_nt[j] : a0;
        for (int a = a0; a < a_rot; ++a) set(A_b, a, b, ws.P.col(a).dot(c.pi));
        const Vec3 w = c.sigma + (ws.o[k] - ws.o[j]).cross(c.pi);
        for (int a = a_rot; a < a0 + m.body_nu[j]; ++a) set(A_b, a, b, ws.P.col(a).dot(w));
      }
    }
  }
}

}  // namespace

void formA(const Model& m, Workspace& ws) {
  if (m.has_sliding) formAImpl<true>(m, ws);
  else formAImpl<false>(m, ws);
}

void multiplyK(const Model& m, const Eigen::VectorXd& x, Workspace& ws, Eigen::VectorXd& Kx) {
  // (K x)_j = K_jj x_j + sum_children d_c x z_c + s_j x y_j, with
  // z_k = sum over subtree(k) of x_i x s_i and y_j = y_p + x_p x d_j (docs/theory.md §5).
  const int n = m.n();
  for (int k = n - 1; k >= 0; --k) {
    ws.z[k] = x.segment<3>(3 * k).cross(ws.s[k]);
    for (int c : m.bodies[k].children) ws.z[k] += ws.z[c];
  }
  for (int j = 0; j < n; ++j) {
    const int p = m.bodies[j].parent;
    ws.y[j] = p < 0 ? Vec3::Zero() : Vec3(ws.y[p] + x.segment<3>(3 * p).cross(ws.d[j]));
    Vec3 out = ws.Kd[j] * x.segment<3>(3 * j) + ws.s[j].cross(ws.y[j]);
    for (int c : m.bodies[j].children) out += ws.d[c].cross(ws.z[c]);
    Kx.segment<3>(3 * j) = out;
  }
}

namespace {

// F~_k: F_k plus the subtree's mass times the linear acceleration the
// velocity-product angular accelerations phi cause (tau_i + phi_i x b_i,
// tau_i = tau_p + phi_p x d_i): the force a slide's row of B projects
// (docs/theory.md eq. (T5)). O(n); sliding scenes only.
void formSlideForces(const Model& m, Workspace& ws) {
  const int n = m.n();
  for (int i = 0; i < n; ++i) {
    const int p = m.bodies[i].parent;
    ws.tau[i] = p < 0 ? Vec3::Zero() : Vec3(ws.tau[p] + ws.phi.segment<3>(3 * p).cross(ws.d[i]));
  }
  for (int k = n - 1; k >= 0; --k) {  // phi's part alone, bottom-up, then F added
    ws.F_slide[k] = m.bodies[k].mass * (ws.tau[k] + ws.phi.segment<3>(3 * k).cross(ws.b[k]));
    for (int c : m.bodies[k].children) ws.F_slide[k] += ws.F_slide[c];
  }
  for (int k = 0; k < n; ++k) ws.F_slide[k] += ws.F[k];
}

// phi = T^T f and the joint points' velocity-product accelerations e, h (§5;
// a slide adds Coriolis 2 w_p x v_rel to e, eq. (T4)).
void formVelocityProducts(const Model& m, const double* u, Workspace& ws) {
  for (int i = 0; i < m.n(); ++i) {
    const Body& body = m.bodies[i];
    const int p = body.parent, nt = body.nt(), nr = body.nu() - nt;
    const Vec3& w = ws.omega[i];
    // phi_i = (T^T f)_i: velocity-product angular acceleration of body i, summed down the tree.
    Vec3 phi_i = Vec3::Zero();
    for (int k = body.iu + nt; k < body.iu + nt + nr; ++k) phi_i += ws.Pdot.col(k) * u[k];
    // e_i: velocity-product acceleration of joint point i, from the parent's joint point.
    Vec3 e_i = Vec3::Zero();
    if (p >= 0) {
      phi_i += ws.phi.segment<3>(3 * p);
      e_i = ws.e[p] + ws.omega[p].cross(ws.omega[p].cross(ws.d[i]));
      if (nt > 0) e_i += 2.0 * ws.omega[p].cross(ws.v_rel[i]);
    }
    ws.phi.segment<3>(3 * i) = phi_i;
    ws.e[i] = e_i;
    ws.h[i] = e_i + w.cross(w.cross(ws.b[i]));
  }
}

}  // namespace

void formB(const Model& m, const double* q, const double* u, Workspace& ws) {
  const int n = m.n();
  formVelocityProducts(m, u, ws);
  // F_k = sum over subtree(k) of m_i (h_i - g), bottom-up.
  for (int k = n - 1; k >= 0; --k) {
    ws.F[k] = m.bodies[k].mass * (ws.h[k] - m.gravity);
    for (int c : m.bodies[k].children) ws.F[k] += ws.F[c];
  }
  if (m.has_sliding) formSlideForces(m, ws);
  // psi = K phi + M', M'_j = w_j x J_j w_j + sum_i T_ji m_i l_ji x (h_i - g)
  // (barycentric: l_ji is d_c for every i below child c).
  multiplyK(m, ws.phi, ws, ws.psi);
  for (int j = 0; j < n; ++j) {
    const Body& Bj = m.bodies[j];
    const Vec3& w = ws.omega[j];
    Vec3 Mp = w.cross(ws.J_w[j] * w) + Bj.mass * ws.b[j].cross(ws.h[j] - m.gravity);
    for (int c : Bj.children) Mp += ws.d[c].cross(ws.F[c]);
    ws.psi.segment<3>(3 * j) += Mp;
  }
  // T psi: subtree sums, then B = -P^T (T psi) + Q; a slide's row -t^T F~ (eq. (T5)).
  for (int i = n - 1; i >= 0; --i)
    if (int p = m.bodies[i].parent; p >= 0) ws.psi.segment<3>(3 * p) += ws.psi.segment<3>(3 * i);
  for (int i = 0; i < n; ++i) {
    const Body& body = m.bodies[i];
    const int nt = body.nt(), nr = body.nu() - nt;
    if (nt > 0) ws.B.segment(body.iu, nt).noalias() = -(ws.P.middleCols(body.iu, nt).transpose() * ws.F_slide[i]);
    ws.B.segment(body.iu + nt, nr).noalias() = -(ws.P.middleCols(body.iu + nt, nr).transpose() * ws.psi.segment<3>(3 * i));
  }
  if (m.hasAppliedForces()) addAppliedForces(m, ws, q, u, ws.B);
}

void formSubtreeRates(const Model& m, Workspace& ws) {
  // Bottom-up like formSubtrees; docs/theory.md §6.
  for (int k = m.n() - 1; k >= 0; --k) {
    const Body& body = m.bodies[k];
    const Vec3 mv = body.mass * ws.v[k];
    const Mat3 W = skew(ws.omega[k]);
    ws.L[k] = mv;
    ws.JW[k] = W * ws.J_w[k] - ws.J_w[k] * W;  // J_k'
    ws.Gamma[k] = kernel(mv, ws.b[k]) + kernel(ws.b[k], mv);
    for (int c : body.children) {
      const Vec3& d = ws.d[c];
      ws.L[k] += ws.L[c];
      ws.JW[k] += ws.JW[c];
      ws.Gamma[k] += ws.Gamma[c] + kernel(ws.L[c], d) + kernel(d, ws.L[c]);
    }
  }
  for (int k = 0; k < m.n(); ++k) {
    const Vec3& vo = ws.vo[k];
    ws.S_dot[k] = ws.L[k] - ws.mu[k] * vo;
    ws.IC_dot[k] = ws.JW[k] + ws.Gamma[k] - kernel(vo, ws.S[k]) - kernel(ws.S[k], vo);
  }
}

namespace {

// formA's column momentum (sigma, pi) and its rate (sigma', pi') (docs/theory.md §6, eqs. (T2)–(T3) differentiated).
template <bool kSliding>
void columnMomentumRate(const Workspace& ws, int k, const Vec3& p_b, const Vec3& pd_b, bool slides,
                        ColumnMomentum& c, ColumnMomentum& c_dot) {
  c = columnMomentum<kSliding>(ws, k, p_b, slides);
  if (kSliding && slides) {
    c_dot = {ws.S_dot[k].cross(p_b) + ws.S[k].cross(pd_b), ws.mu[k] * pd_b};
    return;
  }
  c_dot = {ws.IC_dot[k] * p_b + ws.IC[k] * pd_b, pd_b.cross(ws.S[k]) + p_b.cross(ws.S_dot[k])};
}

template <bool kSliding>
void formAdotImpl(const Model& m, Workspace& ws) {
  // The time derivative of formA's A_ab = p_a . w, w = sigma + r_jk x pi
  // (t_a . pi for a slide): A'_ab = p_a' . w + p_a . w', column by column and mirrored as in formA.
  const int N = m.nu;
  const auto set = [&ws, N](double* Ad_b, int a, int b, double value) {
    if (a > b) return;
    Ad_b[a] = value;
    ws.Adot.data()[static_cast<size_t>(a) * N + b] = value;
  };
  for (int k = 0; k < m.n(); ++k) {
    const int b0 = m.body_iu[k];
    for (int b = b0; b < b0 + m.body_nu[k]; ++b) {
      ColumnMomentum c, c_dot;
      columnMomentumRate<kSliding>(ws, k, ws.P.col(b), ws.Pdot.col(b), b < b0 + m.body_nt[k], c, c_dot);
      double* Ad_b = ws.Adot.data() + static_cast<size_t>(b) * N;  // column b
      for (int j = k; j >= 0; j = m.body_parent[j]) {
        const int a0 = m.body_iu[j], a_rot = kSliding ? a0 + m.body_nt[j] : a0;
        for (int a = a0; a < a_rot; ++a) set(Ad_b, a, b, ws.Pdot.col(a).dot(c.pi) + ws.P.col(a).dot(c_dot.pi));
        const Vec3 r = ws.o[k] - ws.o[j], r_dot = ws.vo[k] - ws.vo[j];
        const Vec3 w = c.sigma + r.cross(c.pi);
        const Vec3 w_dot = c_dot.sigma + r_dot.cross(c.pi) + r.cross(c_dot.pi);
        for (int a = a_rot; a < a0 + m.body_nu[j]; ++a) set(Ad_b, a, b, ws.Pdot.col(a).dot(w) + ws.P.col(a).dot(w_dot));
      }
    }
  }
}

}  // namespace

void formAdot(const Model& m, Workspace& ws) {
  if (m.has_sliding) formAdotImpl<true>(m, ws);
  else formAdotImpl<false>(m, ws);
}

void formEquations(const Model& m, const double* q, const double* u, Workspace& ws, bool with_Adot, bool with_A) {
  formKinematics(m, q, u, ws);
  formSubtrees(m, ws);
  if (with_A) formA(m, ws);
  formB(m, q, u, ws);
  if (!with_Adot) return;
  formSubtreeRates(m, ws);
  formAdot(m, ws);
}

Workspace equationsAtStart(const Model& m) {
  Workspace ws(m);
  const Eigen::VectorXd q = m.q0(), u = m.u0();
  formEquations(m, q.data(), u.data(), ws);
  formEnergies(m, q.data(), ws);
  return ws;
}

void formQdot(const Model& m, const double* q, const double* u, double* qdot) {
  for (const Body& body : m.bodies) jointQdot(body.joint, q + body.iq, u + body.iu, qdot + body.iq);
}

void normalizeQuaternions(const Model& m, double* q) {
  for (const Body& b : m.bodies)
    if (const int at = jointQuat(b.joint.type); at >= 0) Eigen::Map<Vec4>(q + b.iq + at).normalize();
}

double conditionNumber(const Eigen::MatrixXd& A) {
  if (!A.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A, Eigen::EigenvaluesOnly).eigenvalues();
  if (!(lambda[0] > 0)) return std::numeric_limits<double>::infinity();
  return lambda[lambda.size() - 1] / lambda[0];
}

}  // namespace em
