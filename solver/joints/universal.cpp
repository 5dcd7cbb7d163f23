// The universal joint (docs/theory.md §1): q0 about e0 fixed in the parent,
// then q1 about e1 fixed in the body, R = Rot(e0, q0) Rot(e1, q1).
#include "solver/joints/kind_tools.hpp"

namespace em {

namespace {

Mat3 rotation(const Joint& j, const double* q) { return rot(j.axis[0], q[0]) * rot(j.axis[1], q[1]); }

void axes(const Joint& j, const Mat3& R_p, const double* q, Axes& P) {
  P.resize(3, 2);
  P.col(0) = R_p * j.axis[0];
  P.col(1) = R_p * (rot(j.axis[0], q[0]) * j.axis[1]);
}

// The first axis turns with the parent, the second with the body.
void axisRates(const Joint&, const Axes& P, const Vec3& omega_p, const Vec3& omega_b, const double*, Axes& Pdot) {
  Pdot.resize(3, 2);
  Pdot.col(0) = omega_p.cross(P.col(0));
  Pdot.col(1) = omega_b.cross(P.col(1));
}

// R e1 = Rot(e0, q0) e1: q0 turns e1 to R e1 about e0, then q1 is what is left about e1.
void coordinates(const Joint& j, const Mat3& R, const Vec3&, const double* near, double* q) {
  const Vec3 &a0 = j.axis[0], &a1 = j.axis[1];
  const Vec3 from = a1 - a0.dot(a1) * a0, to = R * a1 - a0.dot(R * a1) * a0;
  q[0] = joints::unwrapNear(std::atan2(a0.dot(from.cross(to)), from.dot(to)), near[0]);
  q[1] = joints::unwrapNear(joints::angleAbout(a1, rot(a0, q[0]).transpose() * R), near[1]);
}

}  // namespace

const JointKinematics kUniversalKinematics = {rotation, joints::noSlide, axes, axisRates, coordinates,
                                              joints::wholeSeparation};

}  // namespace em
