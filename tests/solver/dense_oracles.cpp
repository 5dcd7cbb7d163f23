// The dense oracles of the formation (docs/theory.md §4, §6): K by its
// barycentric blocks and by the naive triple sum, K_T = T K T^T, and A, A'
// projected block by block from them. Only tests call them (as Pinocchio
// keeps its reference implementations in its unit tests).
#include "solver/dense_oracles.hpp"

#include "solver/rotation.hpp"

namespace em::test {

namespace {

// (a . b) E - b (x) a: the dyadic kernel of K (docs/theory.md §4), written again here.
Mat3 kernel(const Vec3& a, const Vec3& b) { return a.dot(b) * Mat3::Identity() - b * a.transpose(); }

// In-place T X T^T on a (3n x 3n) block matrix: T sums over subtrees, and with
// regular numbering a descending sweep that adds each block row (column) into
// its parent's completes every subtree before it is used.
void applyTXTt(const Model& m, Eigen::MatrixXd& X) {
  for (int i = m.n() - 1; i >= 0; --i)
    if (int p = m.bodies[i].parent; p >= 0) X.middleRows<3>(3 * p) += X.middleRows<3>(3 * i);
  for (int i = m.n() - 1; i >= 0; --i)
    if (int p = m.bodies[i].parent; p >= 0) X.middleCols<3>(3 * p) += X.middleCols<3>(3 * i);
}

// out = P^T X P block by block: P is block diagonal, so block (j,k) of the
// (nu x nu) result is P_j^T X_jk P_k (docs/theory.md §4, eq. (2)).
void projectBlocks(const Model& m, const Eigen::MatrixXd& X, const Eigen::Matrix3Xd& Pl,
                   const Eigen::Matrix3Xd& Pr, Eigen::MatrixXd& out, bool accumulate = false) {
  Axes XP;
  for (const Body& Bj : m.bodies) {
    const int j = &Bj - m.bodies.data();
    for (const Body& Bk : m.bodies) {
      const int k = &Bk - m.bodies.data();
      XP.noalias() = X.block<3, 3>(3 * j, 3 * k) * Pr.middleCols(Bk.iu, Bk.nu());
      auto dst = out.block(Bj.iu, Bk.iu, Bj.nu(), Bk.nu());
      if (accumulate)
        dst.noalias() += Pl.middleCols(Bj.iu, Bj.nu()).transpose() * XP;
      else
        dst.noalias() = Pl.middleCols(Bj.iu, Bj.nu()).transpose() * XP;
    }
  }
}

}  // namespace

Eigen::MatrixXd barycentricK(const Model& m, const Workspace& ws) {
  Eigen::MatrixXd K;
  K.setZero(3 * m.n(), 3 * m.n());
  for (int k = 0; k < m.n(); ++k) {
    const Body& B = m.bodies[k];
    K.block<3, 3>(3 * k, 3 * k) = ws.Kd[k];
    // Off-diagonal with every strict ancestor j: l_ji = d_c for all i in subtree(k).
    for (int c = k, j = B.parent; j >= 0; c = j, j = m.bodies[j].parent) {
      const Mat3 Kjk = kernel(ws.d[c], ws.s[k]);
      K.block<3, 3>(3 * j, 3 * k) = Kjk;
      K.block<3, 3>(3 * k, 3 * j) = Kjk.transpose();
    }
  }
  return K;
}

Eigen::MatrixXd naiveK(const Model& m, const Workspace& ws) {
  const int n = m.n();
  // l_ji: inside body j from joint j toward body i (to CM i when j = i).
  auto l = [&](int j, int i) -> Vec3 {
    if (j == i) return ws.b[i];
    int c = i;
    while (m.bodies[c].parent != j) c = m.bodies[c].parent;
    return ws.d[c];
  };
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(3 * n, 3 * n);
  for (int j = 0; j < n; ++j) {
    K.block<3, 3>(3 * j, 3 * j) += ws.J_w[j];
    for (int k = 0; k < n; ++k)
      for (int i = 0; i < n; ++i)
        if (m.T(j, i) && m.T(k, i))
          K.block<3, 3>(3 * j, 3 * k) += m.bodies[i].mass * kernel(l(j, i), l(k, i));
  }
  return K;
}

DenseK formDenseK(const Model& m, const Workspace& ws) {
  DenseK dk;
  dk.K = barycentricK(m, ws);
  dk.KT = dk.K;
  applyTXTt(m, dk.KT);
  dk.P = ws.P;
  return dk;
}

Eigen::MatrixXd denseA(const Model& m, const DenseK& dk) {
  Eigen::MatrixXd A(m.nu, m.nu);
  projectBlocks(m, dk.KT, dk.P, dk.P, A);
  return A;
}

Eigen::MatrixXd denseAdot(const Model& m, const Workspace& ws, const DenseK& dk) {
  // K': every block is built of vectors fixed in one body, so each vector x
  // fixed in body j has x' = w_j x x (docs/theory.md §6).
  Eigen::MatrixXd Kdot = Eigen::MatrixXd::Zero(3 * m.n(), 3 * m.n());
  for (int k = 0; k < m.n(); ++k) {
    const Mat3 W = skew(ws.omega[k]);
    const Mat3 Kkk = dk.K.block<3, 3>(3 * k, 3 * k);
    Kdot.block<3, 3>(3 * k, 3 * k) = W * Kkk - Kkk * W;
    const Vec3& s = ws.s[k];
    const Vec3 s_dot = ws.omega[k].cross(s);
    for (int c = k, j = m.bodies[k].parent; j >= 0; c = j, j = m.bodies[j].parent) {
      const Vec3& d = ws.d[c];
      const Vec3 d_dot = ws.omega[j].cross(d);
      const Mat3 Kjk_dot = kernel(d_dot, s) + kernel(d, s_dot);
      Kdot.block<3, 3>(3 * j, 3 * k) = Kjk_dot;
      Kdot.block<3, 3>(3 * k, 3 * j) = Kjk_dot.transpose();
    }
  }
  Eigen::MatrixXd KTdot = Kdot;
  applyTXTt(m, KTdot);
  // A' = P'^T K_T P + P^T K_T' P + P^T K_T P'; the first is the transpose of the last.
  Eigen::MatrixXd Adot(m.nu, m.nu);
  projectBlocks(m, dk.KT, ws.P, ws.Pdot, Adot);
  for (int a = 0; a < m.nu; ++a)
    for (int c = a; c < m.nu; ++c) Adot(a, c) = Adot(c, a) = Adot(a, c) + Adot(c, a);
  projectBlocks(m, KTdot, ws.P, ws.P, Adot, true);
  return Adot;
}

}  // namespace em::test
