// The free joint (docs/theory.md §12): q = [x (3), quaternion (4)], the
// joint point slides by x along the parent's axes, then the body turns about
// it; u = [v, w], both in the parent frame.
#include "solver/joints/kind_tools.hpp"

namespace em {

namespace {

Mat3 rotation(const Joint&, const double* q) { return quatToMatrix(Vec4(q[3], q[4], q[5], q[6])); }

Vec3 slide(const Joint&, const double* q) { return Vec3(q[0], q[1], q[2]); }

// Slides along, then turns about, the parent's axes.
void axes(const Joint&, const Mat3& R_p, const double*, Axes& P) {
  P.resize(3, 6);
  P << R_p, R_p;
}

void coordinates(const Joint&, const Mat3& R, const Vec3& x, const double* near, double* q) {
  Eigen::Map<Vec3>{q} = x;
  joints::quatNear(R, near + 3, q + 3);
}

double separation(const Joint&, const Vec3&) { return 0; }  // it takes any displacement

}  // namespace

const JointKinematics kFreeKinematics = {rotation, slide, axes, joints::axesTurnWithParent, coordinates, separation};

}  // namespace em
