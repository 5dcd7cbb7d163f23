// The kinematics of every joint kind, through its row (solver/model.hpp):
// each kind's own file (solver/joints/<kind>.cpp) holds its functions; what
// follows from the row alone (q' from u, speeds from a motion) is here.
#include "solver/joint.hpp"

namespace em {

namespace {
const JointKinematics& of(const Joint& j) { return *jointRow(j.type).kinematics; }
}  // namespace

Mat3 relativeRotation(const Joint& j, const double* q) { return of(j).rotation(j, q); }

Vec3 slideOffset(const Joint& j, const double* q) { return of(j).slide(j, q); }

void worldAxes(const Joint& j, const Mat3& R_p, const double* q, Axes& P) { of(j).axes(j, R_p, q, P); }

void axisRates(const Joint& j, const Axes& P, const Vec3& omega_p, const Vec3& omega_b, const double* u, Axes& Pdot) {
  of(j).axis_rates(j, P, omega_p, omega_b, u, Pdot);
}

void jointCoordinates(const Joint& j, const Mat3& R, const Vec3& x, const double* near, double* q) {
  of(j).coordinates(j, R, x, near, q);
}

double jointSeparation(const Joint& j, const Vec3& x) { return of(j).separation(j, x); }

void jointQdot(const Joint& j, const double* q, const double* u, double* qdot) {
  const int at = jointQuat(j.type), nt = jointNt(j.type);
  if (at < 0) {
    for (int k = 0; k < jointNu(j.type); ++k) qdot[k] = u[k];
    return;
  }
  for (int k = 0; k < nt; ++k) qdot[k] = u[k];
  const double *qq = q + at, *w = u + nt;
  const Vec4 d = 0.5 * quatMul(Vec4(0, w[0], w[1], w[2]), Vec4(qq[0], qq[1], qq[2], qq[3]));
  for (int k = 0; k < 4; ++k) qdot[at + k] = d[k];
}

void jointSpeeds(const Joint& j, const double* q, const Vec3& w, const Vec3& xdot, double* u) {
  const int nt = jointNt(j.type), nu = jointNu(j.type);
  Axes P;
  worldAxes(j, Mat3::Identity(), q, P);  // parent frame: the sliding directions, then the rotation axes
  for (int k = 0; k < nt; ++k) u[k] = P.col(k).dot(xdot);  // the sliding axes are orthonormal
  if (nt == nu) return;
  const Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3> E = P.rightCols(nu - nt);
  const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> wr = E.colPivHouseholderQr().solve(w);
  for (int k = 0; k < nu - nt; ++k) u[nt + k] = wr[k];
}

}  // namespace em
