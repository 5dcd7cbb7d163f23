// The gimbal (docs/theory.md §1): body-fixed x-y-z Cardan angles,
// R = Rx(q0) Ry(q1) Rz(q2); A loses rank at a middle angle of +-90 deg.
#include "solver/joints/kind_tools.hpp"

#include <algorithm>

namespace em {

namespace {

Mat3 rotation(const Joint&, const double* q) {
  return rot(Vec3::UnitX(), q[0]) * rot(Vec3::UnitY(), q[1]) * rot(Vec3::UnitZ(), q[2]);
}

// Body-fixed x-y-z: axis k is fixed in the frame after the first k-1 rotations.
void axes(const Joint&, const Mat3& R_p, const double* q, Axes& P) {
  P.resize(3, 3);
  const Mat3 R1 = R_p * rot(Vec3::UnitX(), q[0]);
  P.col(0) = R_p.col(0);
  P.col(1) = R1.col(1);
  P.col(2) = R1 * rot(Vec3::UnitY(), q[1]).col(2);
}

// Axis 0 turns with the parent, axis 1 with the intermediate frame, axis 2 with the body.
void axisRates(const Joint&, const Axes& P, const Vec3& omega_p, const Vec3& omega_b, const double* u, Axes& Pdot) {
  Pdot.resize(3, 3);
  Pdot.col(0) = omega_p.cross(P.col(0));
  Pdot.col(1) = (omega_p + P.col(0) * u[0]).cross(P.col(1));
  Pdot.col(2) = omega_b.cross(P.col(2));
}

// The angles of R, on the nearer of R's two branches to `near`.
void coordinates(const Joint&, const Mat3& R, const Vec3&, const double* near, double* q) {
  const double b = std::asin(std::clamp(R(0, 2), -1.0, 1.0));
  const double a = std::atan2(-R(1, 2), R(2, 2)), c = std::atan2(-R(0, 1), R(0, 0));
  const Vec3 branch[2] = {{a, b, c}, {a + M_PI, M_PI - b, c + M_PI}};
  Vec3 best = branch[0];
  double best_d = HUGE_VAL;
  for (Vec3 x : branch) {
    for (int k = 0; k < 3; ++k) x[k] = joints::unwrapNear(x[k], near[k]);
    const double d = (x - Vec3(near)).squaredNorm();
    if (d < best_d) best_d = d, best = x;
  }
  Eigen::Map<Vec3>{q} = best;
}

}  // namespace

const JointKinematics kGimbalKinematics = {rotation, joints::noSlide, axes, axisRates, coordinates, joints::wholeSeparation};

}  // namespace em
