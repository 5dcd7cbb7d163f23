#include "solver/joint.hpp"

#include <algorithm>
#include <cmath>

namespace em {

Mat3 relativeRotation(const Joint& j, const double* q) {
  switch (j.type) {
    case JointType::Revolute: return rot(j.axis[0], q[0]);
    case JointType::Universal: return rot(j.axis[0], q[0]) * rot(j.axis[1], q[1]);
    case JointType::Gimbal:
      return rot(Vec3::UnitX(), q[0]) * rot(Vec3::UnitY(), q[1]) * rot(Vec3::UnitZ(), q[2]);
    case JointType::Ball: return quatToMatrix(Vec4(q[0], q[1], q[2], q[3]));
    case JointType::Prismatic: return Mat3::Identity();
    case JointType::Free: return quatToMatrix(Vec4(q[3], q[4], q[5], q[6]));
  }
  return Mat3::Identity();
}

Vec3 slideOffset(const Joint& j, const double* q) {
  switch (j.type) {
    case JointType::Prismatic: return q[0] * j.axis[0];
    case JointType::Free: return Vec3(q[0], q[1], q[2]);
    case JointType::Revolute:
    case JointType::Universal:
    case JointType::Gimbal:
    case JointType::Ball: return Vec3::Zero();  // they turn about the joint point
  }
  return Vec3::Zero();
}

void worldAxes(const Joint& j, const Mat3& R_p, const double* q, Axes& P) {
  P.resize(3, jointNu(j.type));
  switch (j.type) {
    case JointType::Revolute:
    case JointType::Prismatic: P.col(0) = R_p * j.axis[0]; break;
    case JointType::Universal:
      P.col(0) = R_p * j.axis[0];
      P.col(1) = R_p * (rot(j.axis[0], q[0]) * j.axis[1]);
      break;
    case JointType::Gimbal: {
      // Body-fixed x-y-z: axis k is fixed in the frame after the first k-1 rotations.
      const Mat3 R1 = R_p * rot(Vec3::UnitX(), q[0]);
      P.col(0) = R_p.col(0);
      P.col(1) = R1.col(1);
      P.col(2) = R1 * rot(Vec3::UnitY(), q[1]).col(2);
      break;
    }
    case JointType::Ball: P = R_p; break;
    case JointType::Free: P << R_p, R_p; break;  // slides along, then turns about, the parent's axes
  }
}

void axisRates(const Joint& j, const Axes& P, const Vec3& omega_p, const Vec3& omega_b,
               const double* u, Axes& Pdot) {
  Pdot.resize(3, P.cols());
  // An axis fixed in a frame turns with that frame's angular velocity: p' = w x p.
  switch (j.type) {
    case JointType::Revolute:
    case JointType::Ball:
    case JointType::Prismatic:
    case JointType::Free:
      for (int k = 0; k < P.cols(); ++k) Pdot.col(k) = omega_p.cross(P.col(k));
      break;
    case JointType::Universal:
      Pdot.col(0) = omega_p.cross(P.col(0));
      Pdot.col(1) = omega_b.cross(P.col(1));
      break;
    case JointType::Gimbal:
      Pdot.col(0) = omega_p.cross(P.col(0));
      Pdot.col(1) = (omega_p + P.col(0) * u[0]).cross(P.col(1));
      Pdot.col(2) = omega_b.cross(P.col(2));
      break;
  }
}

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

namespace {

// x - 2 pi k nearest `near`.
double unwrapNear(double x, double near) { return x - 2 * M_PI * std::round((x - near) / (2 * M_PI)); }

// The angle of R about unit axis a (R a rotation about a).
double angleAbout(const Vec3& a, const Mat3& R) {
  const Vec3 s(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));  // 2 sin(q) a
  return std::atan2(0.5 * a.dot(s), 0.5 * (R.trace() - 1));
}

// Euler angles x-y-z of R = Rx(a) Ry(b) Rz(c), the branch nearest `near`.  // near: (3)
Vec3 gimbalAngles(const Mat3& R, const double* near) {
  const double b = std::asin(std::clamp(R(0, 2), -1.0, 1.0));
  const double a = std::atan2(-R(1, 2), R(2, 2)), c = std::atan2(-R(0, 1), R(0, 0));
  const Vec3 branch[2] = {{a, b, c}, {a + M_PI, M_PI - b, c + M_PI}};
  Vec3 best = branch[0];
  double best_d = HUGE_VAL;
  for (Vec3 x : branch) {
    for (int k = 0; k < 3; ++k) x[k] = unwrapNear(x[k], near[k]);
    const double d = (x - Vec3(near)).squaredNorm();
    if (d < best_d) best_d = d, best = x;
  }
  return best;
}

// The unit quaternion of R in the hemisphere of `near`.  // near, q: (4)
void quatNear(const Mat3& R, const double* near, double* q) {
  Vec4 r = matrixToQuat(R);
  if (r.dot(Vec4(near[0], near[1], near[2], near[3])) < 0) r = -r;
  for (int k = 0; k < 4; ++k) q[k] = r[k];
}

}  // namespace

void jointCoordinates(const Joint& j, const Mat3& R, const Vec3& x, const double* near, double* q) {
  switch (j.type) {
    case JointType::Revolute: q[0] = unwrapNear(angleAbout(j.axis[0], R), near[0]); return;
    case JointType::Universal: {  // R a1 = rot(a0, q0) a1: q0 turns a1 to R a1 about a0
      const Vec3 &a0 = j.axis[0], &a1 = j.axis[1];
      const Vec3 from = a1 - a0.dot(a1) * a0, to = R * a1 - a0.dot(R * a1) * a0;
      q[0] = unwrapNear(std::atan2(a0.dot(from.cross(to)), from.dot(to)), near[0]);
      q[1] = unwrapNear(angleAbout(a1, rot(a0, q[0]).transpose() * R), near[1]);
      return;
    }
    case JointType::Gimbal: Eigen::Map<Vec3>{q} = gimbalAngles(R, near); return;
    case JointType::Ball: quatNear(R, near, q); return;
    case JointType::Prismatic: q[0] = j.axis[0].dot(x); return;
    case JointType::Free:
      Eigen::Map<Vec3>{q} = x;
      quatNear(R, near + 3, q + 3);
      return;
  }
}

void jointSpeeds(const Joint& j, const double* q, const Vec3& w, const Vec3& xdot, double* u) {
  const int nt = jointNt(j.type), nu = jointNu(j.type);
  Axes P;
  worldAxes(j, Mat3::Identity(), q, P);  // parent frame: the sliding directions, then the rotation axes
  if (nt == nu) {  // prismatic
    u[0] = P.col(0).dot(xdot);
    return;
  }
  for (int k = 0; k < nt; ++k) u[k] = xdot[k];  // free: x' itself
  const Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3> E = P.rightCols(nu - nt);
  const Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 3, 1> wr = E.colPivHouseholderQr().solve(w);
  for (int k = 0; k < nu - nt; ++k) u[nt + k] = wr[k];
}

double jointSeparation(const Joint& j, const Vec3& x) {
  switch (j.type) {
    case JointType::Prismatic: return (x - j.axis[0].dot(x) * j.axis[0]).norm();
    case JointType::Free: return 0;
    case JointType::Revolute:
    case JointType::Universal:
    case JointType::Gimbal:
    case JointType::Ball: return x.norm();
  }
  return x.norm();
}

}  // namespace em
