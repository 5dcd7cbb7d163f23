// The rows closure kinds are made of (docs/theory.md §15).
#include "solver/mechanism/loop_rows.hpp"

#include <cmath>

namespace em {

void perpendicularPair(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 seed = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  t1 = n.cross(seed).normalized();
  t2 = n.cross(t1);
}

double angleBetween(const Vec3& e, const Vec3& f) { return std::atan2(e.cross(f).norm(), e.dot(f)); }

namespace {

// The angle of the rotation Q (accurate near 0: from its skew part and its trace).
double rotationAngle(const Mat3& Q) {
  const Vec3 s(Q(2, 1) - Q(1, 2), Q(0, 2) - Q(2, 0), Q(1, 0) - Q(0, 1));
  return std::atan2(0.5 * s.norm(), 0.5 * (Q.trace() - 1));
}

}  // namespace

double pointGap(const Loop&, const Vec3& xa, const Vec3& xb, const Mat3&) { return (xb - xa).norm(); }

double lineGap(const Loop& l, const Vec3& xa, const Vec3& xb, const Mat3& Ra) {
  const Vec3 n = Ra * l.axis_a, d = xb - xa;
  return (d - n.dot(d) * n).norm();
}

void pointRows(const LoopContext& x, int r, LoopState& ls) {
  const Loop& l = x.loop;
  const PointMotion pa = pointMotion(x.ws, l.a), pb = pointMotion(x.ws, l.b);
  ls.g.segment<3>(r) = pa.x - pb.x;
  auto rows = ls.G.middleRows(r, 3);
  if (l.a.body >= 0) addPointJacobian(x.m, x.ws, l.a.body, pa.x, 1.0, rows);
  if (l.b.body >= 0) addPointJacobian(x.m, x.ws, l.b.body, pb.x, -1.0, rows);
  ls.c.segment<3>(r) = (l.a.body < 0 ? Vec3::Zero() : pointBias(x.m, x.ws, x.u, l.a.body, pa.x, pa.v)) -
                       (l.b.body < 0 ? Vec3::Zero() : pointBias(x.m, x.ws, x.u, l.b.body, pb.x, pb.v));
}

// g_k = t_k . d, d = x_b - x_a, t_k = R_a t_k0. With t_k' = omega_a x t_k:
//   g_k' = t_k . (J_b - J_a) u + (t_k x d) . J_w,a u,
//   c_k  = t_k . (J_b' - J_a') u + (alpha0_a x t_k + omega_a x (omega_a x t_k)) . d + 2 (omega_a x t_k) . d',
// alpha0_a and J' u the velocity-product parts (angularBias, pointBias).
void lineRows(const LoopContext& x, int r, LoopState& ls) {
  const Loop& l = x.loop;
  const PointMotion pa = pointMotion(x.ws, l.a), pb = pointMotion(x.ws, l.b);
  const Mat3 Ra = rotationOf(x.ws, l.a.body);
  const Vec3 wa = omegaOf(x.ws, l.a.body);
  Vec3 t0[2];
  perpendicularPair(l.axis_a, t0[0], t0[1]);
  const Vec3 d = pb.x - pa.x, ddot = pb.v - pa.v;
  const Vec3 bias_b = l.b.body < 0 ? Vec3::Zero() : pointBias(x.m, x.ws, x.u, l.b.body, pb.x, pb.v);
  const Vec3 bias_a = l.a.body < 0 ? Vec3::Zero() : pointBias(x.m, x.ws, x.u, l.a.body, pa.x, pa.v);
  const Vec3 alpha_a = l.a.body < 0 ? Vec3::Zero() : angularBias(x.m, x.ws, x.u, l.a.body);
  for (int j : x.speeds) ls.Jw.col(j).setZero();
  if (l.a.body >= 0) addAngularJacobian(x.m, x.ws, l.a.body, 1.0, ls.Jw);
  for (int k = 0; k < 2; ++k) {
    const Vec3 t = Ra * t0[k], tdot = wa.cross(t);
    ls.g[r + k] = t.dot(d);
    auto row = ls.G.row(r + k);
    if (l.b.body >= 0) forPointColumns(x.m, x.ws, l.b.body, pb.x, [&](int j, const Vec3& col) { row[j] += t.dot(col); });
    if (l.a.body >= 0) forPointColumns(x.m, x.ws, l.a.body, pa.x, [&](int j, const Vec3& col) { row[j] -= t.dot(col); });
    const Vec3 txd = t.cross(d);
    for (int j : x.speeds) row[j] += txd.dot(ls.Jw.col(j));
    ls.c[r + k] = t.dot(bias_b - bias_a) + (alpha_a.cross(t) + wa.cross(tdot)).dot(d) + 2.0 * tdot.dot(ddot);
  }
}

RelativeTurn relativeTurn(const LoopContext& x, LoopState& ls) {
  const Loop& l = x.loop;
  for (int j : x.speeds) ls.Jw.col(j).setZero();
  if (l.a.body >= 0) addAngularJacobian(x.m, x.ws, l.a.body, 1.0, ls.Jw);
  if (l.b.body >= 0) addAngularJacobian(x.m, x.ws, l.b.body, -1.0, ls.Jw);
  return {omegaOf(x.ws, l.a.body), omegaOf(x.ws, l.b.body),
          Vec3((l.a.body < 0 ? Vec3::Zero() : angularBias(x.m, x.ws, x.u, l.a.body)) -
               (l.b.body < 0 ? Vec3::Zero() : angularBias(x.m, x.ws, x.u, l.b.body))),
          &x.speeds};
}

void pairRow(const RelativeTurn& turn, const Vec3& e, const Vec3& f, int r, LoopState& ls) {
  const Vec3 n = e.cross(f);
  ls.g[r] = e.dot(f);
  for (int j : *turn.speeds) ls.G(r, j) = n.dot(ls.Jw.col(j));
  const Vec3 ndot = turn.wa.cross(e).cross(f) + e.cross(turn.wb.cross(f));
  ls.c[r] = n.dot(turn.alpha) + ndot.dot(turn.wa - turn.wb);
}

double frameRows(const LoopContext& x, const RelativeTurn& turn, int r, LoopState& ls) {
  const Mat3 A = rotationOf(x.ws, x.loop.a.body) * x.loop.rel;  // b's frame as a holds it
  const Mat3 Rb = rotationOf(x.ws, x.loop.b.body);
  for (int k = 0; k < 3; ++k) pairRow(turn, A.col(k), Rb.col((k + 1) % 3), r + k, ls);
  return rotationAngle(A.transpose() * Rb);
}

}  // namespace em
