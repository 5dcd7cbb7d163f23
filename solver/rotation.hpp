#pragma once
/// Small rotation helpers (world <- body convention, Hamilton quaternions [w,x,y,z]).
#include <Eigen/Dense>

namespace em {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec4 = Eigen::Vector4d;

/// Rotation by angle `q` about unit axis `a` (right-handed).  // (3x3)
Mat3 rot(const Vec3& a, double q);
/// Skew matrix [v]x with [v]x w = v x w.  // (3x3)
Mat3 skew(const Vec3& v);
/// Rotation matrix of the quaternion q = [w,x,y,z] (normalized inside).  // (3x3)
Mat3 quatToMatrix(const Vec4& q);
/// Unit quaternion [w,x,y,z] of a rotation matrix, w >= 0.  // (4)
Vec4 matrixToQuat(const Mat3& R);
/// Hamilton product a (x) b of quaternions [w,x,y,z].  // (4)
Vec4 quatMul(const Vec4& a, const Vec4& b);
/// Rotation angle (rad, in [0, pi]) of Ra^T Rb: the coordinate-free distance of two orientations.
double rotationAngleBetween(const Mat3& Ra, const Mat3& Rb);

}  // namespace em
