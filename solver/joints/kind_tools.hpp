#pragma once
/// What several joint kinds' own files share (solver/joints/<kind>.cpp):
/// angles unwrapped near a reference, the angle of a rotation about an axis,
/// a quaternion in a reference's hemisphere, and the common cases of the
/// kinematics' columns (no slide; axes fixed in the parent).
#include <cmath>

#include "solver/model.hpp"

namespace em::joints {

/// x - 2 pi k nearest `near`.
inline double unwrapNear(double x, double near) { return x - 2 * M_PI * std::round((x - near) / (2 * M_PI)); }

/// The angle of R about unit axis a (R a rotation about a).
inline double angleAbout(const Vec3& a, const Mat3& R) {
  const Vec3 s(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));  // 2 sin(q) a
  return std::atan2(0.5 * a.dot(s), 0.5 * (R.trace() - 1));
}

/// The unit quaternion of R in the hemisphere of `near`.  // near, q: (4)
inline void quatNear(const Mat3& R, const double* near, double* q) {
  Vec4 r = matrixToQuat(R);
  if (r.dot(Vec4(near[0], near[1], near[2], near[3])) < 0) r = -r;
  for (int k = 0; k < 4; ++k) q[k] = r[k];
}

/// A kind that only turns: its joint point does not move.
inline Vec3 noSlide(const Joint&, const double*) { return Vec3::Zero(); }

/// Axes fixed in the parent turn with it: p' = w_parent x p (revolute, ball,
/// prismatic, free, planar).
inline void axesTurnWithParent(const Joint&, const Axes& P, const Vec3& omega_p, const Vec3&, const double*, Axes& Pdot) {
  Pdot.resize(3, P.cols());
  for (int k = 0; k < P.cols(); ++k) Pdot.col(k) = omega_p.cross(P.col(k));
}

/// A kind that only turns takes no displacement of its joint point: all of x is separation.
inline double wholeSeparation(const Joint&, const Vec3& x) { return x.norm(); }

}  // namespace em::joints
