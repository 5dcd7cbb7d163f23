// Tier 1 (closed form): rotation helpers against hand-computed values.
#include <catch2/catch.hpp>

#include "solver/rotation.hpp"

using namespace em;

// Round-off of a handful of 3x3 products of unit-size numbers.
constexpr double kRoundoff = 1e-14;

TEST_CASE("rot turns about the axis by the right-hand rule", "[closedform][rotation]") {
  const Mat3 R = rot(Vec3::UnitZ(), M_PI / 2);
  CHECK((R * Vec3::UnitX() - Vec3::UnitY()).norm() < kRoundoff);
  CHECK((skew(Vec3(1, 2, 3)) * Vec3(4, 5, 6) - Vec3(1, 2, 3).cross(Vec3(4, 5, 6))).norm() < kRoundoff);
}

TEST_CASE("quaternion and matrix conversions invert each other and compose", "[closedform][rotation]") {
  const Mat3 Ra = rot(Vec3(1, 2, -1).normalized(), 0.7), Rb = rot(Vec3(0, 1, 3).normalized(), -2.9);
  const Vec4 qa = matrixToQuat(Ra), qb = matrixToQuat(Rb);
  CHECK(qa[0] >= 0);
  CHECK((quatToMatrix(qa) - Ra).norm() < kRoundoff);
  // Hamilton product composes rotations in the same order as matrices.
  CHECK((quatToMatrix(quatMul(qa, qb)) - Ra * Rb).norm() < kRoundoff);
  // A half-turn about x is [0,1,0,0].
  CHECK((matrixToQuat(rot(Vec3::UnitX(), M_PI)) - Vec4(0, 1, 0, 0)).norm() < kRoundoff);
}

TEST_CASE("rotationAngleBetween is the angle of the relative rotation - also near pi", "[closedform][rotation]") {
  const Mat3 R = rot(Vec3(1, 1, 1).normalized(), 1.1);
  for (double a : {1e-9, 0.3, 2.0, M_PI - 1e-7}) {
    const Mat3 R2 = R * rot(Vec3(0.3, -1, 0.2).normalized(), a);
    CHECK(std::abs(rotationAngleBetween(R, R2) - a) < 1e-13);
  }
}
