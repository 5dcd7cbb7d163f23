// The prismatic joint (docs/theory.md §12): the joint point slides q along
// the unit axis e fixed in the parent; no rotation.
#include "solver/joints/kind_tools.hpp"

namespace em {

namespace {

Mat3 rotation(const Joint&, const double*) { return Mat3::Identity(); }

Vec3 slide(const Joint& j, const double* q) { return q[0] * j.axis[0]; }

void axes(const Joint& j, const Mat3& R_p, const double*, Axes& P) {
  P.resize(3, 1);
  P.col(0) = R_p * j.axis[0];
}

void coordinates(const Joint& j, const Mat3&, const Vec3& x, const double*, double* q) { q[0] = j.axis[0].dot(x); }

// Everything but its slide along the axis.
double separation(const Joint& j, const Vec3& x) { return (x - j.axis[0].dot(x) * j.axis[0]).norm(); }

}  // namespace

const JointKinematics kPrismaticKinematics = {rotation, slide, axes, joints::axesTurnWithParent, coordinates, separation};

}  // namespace em
