#include "solver/joint.hpp"

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
    default: return Vec3::Zero();
  }
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

}  // namespace em
