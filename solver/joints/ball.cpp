// The ball joint (docs/theory.md §1): a unit quaternion [w,x,y,z], speeds the
// angular velocity in the parent frame, about the joint point.
#include "solver/joints/kind_tools.hpp"

namespace em {

namespace {

Mat3 rotation(const Joint&, const double* q) { return quatToMatrix(Vec4(q[0], q[1], q[2], q[3])); }

void axes(const Joint&, const Mat3& R_p, const double*, Axes& P) { P = R_p; }

void coordinates(const Joint&, const Mat3& R, const Vec3&, const double* near, double* q) { joints::quatNear(R, near, q); }

}  // namespace

const JointKinematics kBallKinematics = {rotation, joints::noSlide, axes, joints::axesTurnWithParent, coordinates,
                                         joints::wholeSeparation};

}  // namespace em
