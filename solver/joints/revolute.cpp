// The revolute joint (docs/theory.md §1): one angle q about the unit axis e
// fixed in the parent, R = Rot(e, q), about the joint point.
#include "solver/joints/kind_tools.hpp"

namespace em {

namespace {

Mat3 rotation(const Joint& j, const double* q) { return rot(j.axis[0], q[0]); }

void axes(const Joint& j, const Mat3& R_p, const double*, Axes& P) {
  P.resize(3, 1);
  P.col(0) = R_p * j.axis[0];
}

void coordinates(const Joint& j, const Mat3& R, const Vec3&, const double* near, double* q) {
  q[0] = joints::unwrapNear(joints::angleAbout(j.axis[0], R), near[0]);
}

}  // namespace

const JointKinematics kRevoluteKinematics = {rotation, joints::noSlide, axes, joints::axesTurnWithParent, coordinates,
                                             joints::wholeSeparation};

}  // namespace em
