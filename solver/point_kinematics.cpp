// Points fixed in bodies (docs/theory.md §15, eqs. (M2), (M3)).
#include "solver/point_kinematics.hpp"

namespace em {

PointMotion pointMotion(const Workspace& ws, const Attachment& p) {
  if (p.body < 0) return {p.point, Vec3::Zero()};
  const Vec3 rho = ws.R[p.body] * p.point;
  return {ws.r[p.body] + rho, ws.v[p.body] + ws.omega[p.body].cross(rho)};
}

void addPointJacobian(const Model& m, const Workspace& ws, int body, const Vec3& x, double sign,
                      Eigen::Ref<Eigen::MatrixXd> rows) {
  forPointColumns(m, ws, body, x, [&](int j, const Vec3& col) { rows.col(j) += sign * col; });
}

void addAngularJacobian(const Model& m, const Workspace& ws, int body, double sign, Eigen::Ref<Eigen::MatrixXd> rows) {
  for (int k = body; k >= 0; k = m.body_parent[k]) {
    const int iu = m.body_iu[k], nt = m.body_nt[k], nu = m.body_nu[k];
    for (int j = iu + nt; j < iu + nu; ++j) rows.col(j) += sign * ws.P.col(j);
  }
}

Vec3 pointBias(const Model& m, const Workspace& ws, const double* u, int body, const Vec3& x, const Vec3& xdot) {
  Vec3 a = Vec3::Zero();
  for (int k = body; k >= 0; k = m.body_parent[k]) {
    const int iu = m.body_iu[k], nt = m.body_nt[k], nu = m.body_nu[k];
    for (int j = iu; j < iu + nt; ++j) a += ws.Pdot.col(j) * u[j];
    for (int j = iu + nt; j < iu + nu; ++j)
      a += (ws.Pdot.col(j).cross(x - ws.o[k]) + ws.P.col(j).cross(xdot - ws.vo[k])) * u[j];
  }
  return a;
}

Vec3 angularBias(const Model& m, const Workspace& ws, const double* u, int body) {
  Vec3 a = Vec3::Zero();
  for (int k = body; k >= 0; k = m.body_parent[k]) {
    const int iu = m.body_iu[k], nt = m.body_nt[k], nu = m.body_nu[k];
    for (int j = iu + nt; j < iu + nu; ++j) a += ws.Pdot.col(j) * u[j];
  }
  return a;
}

}  // namespace em
