// Joint kinematics: world axes are the angular-velocity directions of the
// relative rotation (checked by finite differences); ball q' and its inverse.
#include <catch2/catch.hpp>

#include <random>

#include "solver/joint.hpp"

using namespace em;

namespace {

// Central-difference step and the tolerance it allows (error ~ h^2 ~ 1e-10,
// plus round-off eps/h ~ 1e-11).
constexpr double kFdStep = 1e-5, kFdTol = 1e-8;

Joint makeJoint(JointType t) {
  Joint j;
  j.type = t;
  j.axis[0] = Vec3(1, 2, 2) / 3.0;
  j.axis[1] = Vec3(0, 1, -1).normalized();
  return j;
}

// Angular velocity (parent frame) of R_rel along coordinate k, by central differences:
// [w]x = R' R^T.
Vec3 fdAxis(const Joint& j, Eigen::VectorXd q, int k) {
  Eigen::VectorXd qp = q, qm = q;
  qp[k] += kFdStep;
  qm[k] -= kFdStep;
  const Mat3 W = (relativeRotation(j, qp.data()) - relativeRotation(j, qm.data())) / (2 * kFdStep) *
                 relativeRotation(j, q.data()).transpose();
  return Vec3(W(2, 1), W(0, 2), W(1, 0));
}

}  // namespace

TEST_CASE("world axes are d(R_rel)/dq_k as angular velocities", "[closedform][joint]") {
  const Mat3 R_p = rot(Vec3(0.2, 1, -0.4).normalized(), 0.8);
  for (JointType t : {JointType::Revolute, JointType::Universal, JointType::Gimbal, JointType::Planar}) {
    const Joint j = makeJoint(t);
    const Eigen::VectorXd q = Eigen::Vector3d(0.3, -0.7, 1.1).head(jointNq(t));
    Axes P;
    worldAxes(j, R_p, q.data(), P);
    for (int k = jointNt(t); k < jointNu(t); ++k) {  // the turning axes (a slide's are checked below)
      INFO(jointTypeName(t) << " axis " << k);
      CHECK((P.col(k) - R_p * fdAxis(j, q, k)).norm() < kFdTol);
    }
  }
}

TEST_CASE("ball: qdot = (0 u) x q / 2 is rotation at angular velocity u in the parent frame", "[closedform][joint]") {
  const Joint j = makeJoint(JointType::Ball);
  const Vec4 q = Vec4(0.9, 0.1, -0.3, 0.2).normalized();
  const Vec3 u(0.4, -1.2, 0.7);
  Vec4 qdot;
  jointQdot(j, q.data(), u.data(), qdot.data());
  // R' R^T = [u]x when u is the angular velocity in the parent frame.
  const Vec4 qp = q + kFdStep * qdot, qm = q - kFdStep * qdot;
  const Mat3 W = (quatToMatrix(qp) - quatToMatrix(qm)) / (2 * kFdStep) * quatToMatrix(q).transpose();
  CHECK((Vec3(W(2, 1), W(0, 2), W(1, 0)) - u).norm() < kFdTol);
  // And back: (0, u) = 2 q' (x) q^-1 for a unit q.
  const Vec4 qc(q[0], -q[1], -q[2], -q[3]);
  const Vec3 back = (2.0 * quatMul(qdot, qc)).tail<3>();
  CHECK((back - u).norm() < 1e-15);
}

TEST_CASE("axis rates are the time derivatives of the world axes", "[closedform][joint]") {
  // Move the parent and the joint along a straight line in (R_p angle, q) and compare.
  for (JointType t : {JointType::Revolute, JointType::Universal, JointType::Gimbal, JointType::Ball, JointType::Prismatic,
                      JointType::Planar}) {
    const Joint j = makeJoint(t);
    const Vec3 a_p = Vec3(0.2, 1, -0.4).normalized();
    const double th_dot = 0.9;  // parent turns about a_p at 0.9 rad/s
    const Eigen::VectorXd u = Eigen::Vector3d(0.5, -0.8, 1.3).head(jointNu(t));
    auto state = [&](double s, Eigen::VectorXd& q, Mat3& R_p) {
      R_p = rot(a_p, 0.3 + th_dot * s);
      q = Eigen::VectorXd::Zero(jointNq(t));
      if (t == JointType::Ball) {
        // integrate q' = 1/2 (0,u) q exactly for constant u: q(s) = exp(s u / 2) q0
        const Vec3 uu = u;
        const Vec4 q0 = Vec4(0.9, 0.1, -0.3, 0.2).normalized();
        const Eigen::Quaterniond qs =
            Eigen::Quaterniond(Eigen::AngleAxisd(uu.norm() * s, uu.normalized())) * Eigen::Quaterniond(q0[0], q0[1], q0[2], q0[3]);
        q = Vec4(qs.w(), qs.x(), qs.y(), qs.z());
      } else {
        q = Eigen::Vector3d(0.3, -0.7, 1.1).head(jointNq(t)) + s * u;
      }
    };
    Eigen::VectorXd q, qp, qm;
    Mat3 R_p, R_pp, R_pm;
    state(0, q, R_p);
    state(kFdStep, qp, R_pp);
    state(-kFdStep, qm, R_pm);
    Axes P, Pp, Pm, Pdot;
    worldAxes(j, R_p, q.data(), P);
    worldAxes(j, R_pp, qp.data(), Pp);
    worldAxes(j, R_pm, qm.data(), Pm);
    const Vec3 w_p = th_dot * a_p;
    const Vec3 w_b = w_p + P * u;
    axisRates(j, P, w_p, w_b, u.data(), Pdot);
    INFO(jointTypeName(t));
    CHECK(((Pp - Pm) / (2 * kFdStep) - Pdot).norm() < kFdTol);
  }
}

TEST_CASE("joint coordinates and speeds read back from a relative pose invert the joint's kinematics", "[closedform][joint]") {
  // The forward maps (relativeRotation, slideOffset, worldAxes) are the
  // oracle: q -> (R, x) -> q and u -> (w, x') -> u at random states, every
  // kind, a universal with skew axes too; angles up to 3 rad (beyond pi/2 for
  // a gimbal's first and last), `near` 0.3 rad off. Round-off: ~1e-15 per
  // operation on unit quantities; 1e-12 leaves room, far below any wrong branch (>= 0.1).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1, 1);
  std::vector<Joint> joints;
  for (const JointTypeInfo& row : jointTypeTable()) joints.push_back(makeJoint(row.type));  // every kind
  joints.push_back(makeJoint(JointType::Universal));
  joints.back().axis[1] = Vec3(0.3, 0.9, -0.1).normalized();  // not perpendicular to axis[0]
  for (const Joint& j : joints)
    for (int trial = 0; trial < 50; ++trial) {
      const int nq = jointNq(j.type), nu = jointNu(j.type), nt = jointNt(j.type), at = jointQuat(j.type);
      Eigen::VectorXd q = 3.0 * Eigen::VectorXd::NullaryExpr(nq, [&] { return uni(rng); });
      if (j.type == JointType::Gimbal) q[1] *= 0.45;  // the middle angle on the principal branch, off the lock
      if (at >= 0) q.segment<4>(at).normalize();
      Eigen::VectorXd near = q + 0.3 * Eigen::VectorXd::NullaryExpr(nq, [&] { return uni(rng); });
      const Eigen::VectorXd u = Eigen::VectorXd::NullaryExpr(nu, [&] { return uni(rng); });
      Eigen::VectorXd back(nq), u_back(nu);
      jointCoordinates(j, relativeRotation(j, q.data()), slideOffset(j, q.data()), near.data(), back.data());
      INFO(jointTypeName(j.type) << " q " << q.transpose() << " read back " << back.transpose());
      CHECK((back - q).cwiseAbs().maxCoeff() <= 1e-12);
      Axes P;
      worldAxes(j, Mat3::Identity(), q.data(), P);
      const Vec3 xdot = nt > 0 ? Vec3(P.leftCols(nt) * u.head(nt)) : Vec3::Zero();
      const Vec3 w = nu > nt ? Vec3(P.rightCols(nu - nt) * u.tail(nu - nt)) : Vec3::Zero();
      jointSpeeds(j, q.data(), w, xdot, u_back.data());
      CHECK((u_back - u).cwiseAbs().maxCoeff() <= 1e-12);
      CHECK(jointSeparation(j, slideOffset(j, q.data())) <= 1e-15);
    }
  const Joint hinge = makeJoint(JointType::Revolute);
  CHECK(jointSeparation(hinge, Vec3(0.3, 0, 0.4)) == Approx(0.5));
}
