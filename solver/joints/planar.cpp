// The planar joint (docs/theory.md §1, §12): q = [s1, s2, theta], the joint
// point slides s1 along e1 and s2 along e2 (perpendicular unit axes fixed in
// the parent), then the body turns theta about n = e1 x e2 about the moved
// joint point: R = Rot(n, theta), x = s1 e1 + s2 e2; u = q'.
#include "solver/joints/kind_tools.hpp"

namespace em {

namespace {

Vec3 normal(const Joint& j) { return j.axis[0].cross(j.axis[1]); }

Mat3 rotation(const Joint& j, const double* q) { return rot(normal(j), q[2]); }

Vec3 slide(const Joint& j, const double* q) { return q[0] * j.axis[0] + q[1] * j.axis[1]; }

void axes(const Joint& j, const Mat3& R_p, const double*, Axes& P) {
  P.resize(3, 3);
  P.col(0) = R_p * j.axis[0];
  P.col(1) = R_p * j.axis[1];
  P.col(2) = R_p * normal(j);
}

void coordinates(const Joint& j, const Mat3& R, const Vec3& x, const double* near, double* q) {
  q[0] = j.axis[0].dot(x);
  q[1] = j.axis[1].dot(x);
  q[2] = joints::unwrapNear(joints::angleAbout(normal(j), R), near[2]);
}

// Its displacement out of the plane.
double separation(const Joint& j, const Vec3& x) { return std::abs(normal(j).dot(x)); }

}  // namespace

const JointKinematics kPlanarKinematics = {rotation, slide, axes, joints::axesTurnWithParent, coordinates, separation};

}  // namespace em
