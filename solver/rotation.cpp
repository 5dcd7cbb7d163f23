#include "solver/rotation.hpp"

#include <algorithm>
#include <cmath>

namespace em {

Mat3 rot(const Vec3& a, double q) { return Eigen::AngleAxisd(q, a).toRotationMatrix(); }

Mat3 skew(const Vec3& v) {
  Mat3 S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

Mat3 quatToMatrix(const Vec4& q) {
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
}

Vec4 matrixToQuat(const Mat3& R) {
  Eigen::Quaterniond e(R);
  Vec4 q(e.w(), e.x(), e.y(), e.z());
  return q[0] < 0 ? Vec4(-q) : q;
}

Vec4 quatMul(const Vec4& a, const Vec4& b) {
  Vec4 r;
  r[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
  r[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
  r[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
  r[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
  return r;
}

double rotationAngleBetween(const Mat3& Ra, const Mat3& Rb) {
  // atan2 of (|vee(skew part)|, (trace-1)/2) is accurate near 0 and near pi, unlike acos.
  const Mat3 D = Ra.transpose() * Rb;
  const Vec3 v(D(2, 1) - D(1, 2), D(0, 2) - D(2, 0), D(1, 0) - D(0, 1));
  return std::atan2(0.5 * v.norm(), 0.5 * (D.trace() - 1.0));
}

}  // namespace em
