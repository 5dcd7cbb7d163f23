// Sliding joints (prismatic, free; docs/theory.md §7) against oracles that are
// not the formation: closed-form Lagrangians (cart-pole, a bead on a turning
// rod), free fall, Euler's equations of a torque-free top, and the momenta a
// free system in zero gravity conserves.
#include <catch2/catch.hpp>

#include <random>

#include "io/urdf.hpp"
#include "solver/formation.hpp"
#include "solver/integrate.hpp"
#include "momenta.hpp"
#include "support.hpp"

using namespace em;

namespace {

// Closed forms of a few products of O(1) numbers: round-off.
constexpr double kClosedForm = 1e-12;

Workspace formAt(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  Workspace ws(m);
  formEquations(m, q.data(), u.data(), ws);
  formEnergies(m, q.data(), ws);
  return ws;
}

// A and B of `m` against a closed form at 20 random states (seed `seed`): `closed`
// gives (A, B) at (q, u); `seen` is called with each state's workspace.
template <class Closed, class Seen>
void checkAgainstClosedForm(const Model& m, unsigned seed, Closed closed, Seen seen) {
  std::mt19937 rng(seed);
  Eigen::VectorXd q, u;
  for (int k = 0; k < 20; ++k) {
    randomState(m, rng, q, u);
    const auto [A, B] = closed(q, u);
    const Workspace ws = formAt(m, q, u);
    INFO("state " << k);
    CHECK(test::relErr(ws.A, A) <= kClosedForm);
    CHECK(test::relErr(ws.B, B) <= kClosedForm);
    seen(ws, B);
  }
}

BodySpec body(const std::string& name, const std::string& parent, double mass, const Mat3& J, JointType type) {
  BodySpec b;
  b.name = name;
  b.parent = parent;
  b.mass = mass;
  b.inertia = J;
  b.joint.type = type;
  b.joint.q0 = Eigen::VectorXd::Zero(jointNq(type));
  if (jointQuat(type) >= 0) b.joint.q0[jointQuat(type)] = 1;
  b.joint.u0 = Eigen::VectorXd::Zero(jointNu(type));
  return b;
}

// A free asymmetric body in zero gravity, its joint point off the CM, tumbling.
Model freeTop() {
  SceneSpec s;
  s.name = "free_top";
  s.gravity = Vec3::Zero();
  Mat3 J = Vec3(0.3, 0.5, 0.65).asDiagonal();
  J(0, 1) = J(1, 0) = 0.04;
  BodySpec b = body("top", "ground", 3.0, J, JointType::Free);
  b.joint.in_parent = Vec3(0.1, 0.2, 0.3);
  b.joint.in_body = Vec3(0.2, -0.1, 0.3);
  b.joint.q0 << 0.1, -0.2, 0.3, 0.9, 0.1, -0.3, 0.2;
  b.joint.q0.tail<4>().normalize();
  b.joint.u0 << 0.3, -0.5, 0.2, 1.5, -2.0, 0.7;
  s.bodies.push_back(b);
  return buildModel(s);
}

std::vector<Method> inhouseMethods() {
  std::vector<Method> out;
  for (const MethodInfo& row : methodTable())
    if (row.make) out.push_back(row.id);
  return out;
}

}  // namespace

TEST_CASE("cart-pole: A and B equal the textbook Lagrangian at random states", "[closedform][sliding]") {
  // Cart (M, on x, spring k, damper c) carrying a pole (m, CM at l below the
  // pin about y, inertia I about y): CM = (x - l sin t, 0, -l cos t).
  // A = [[M+m, -m l cos t], [-m l cos t, m l^2 + I]],
  // B = [-m l sin t t'^2 - k x - c x', -m g l sin t].
  const Model m = test::loadData("cartpole.json");
  REQUIRE(m.has_sliding);
  const double M = 2.0, mp = 0.5, l = 0.5, I = 0.0167, k = 10, c = 0.2, g = 9.81;
  std::mt19937 rng(11);
  Eigen::VectorXd q, u;
  for (int s = 0; s < 20; ++s) {
    randomState(m, rng, q, u);
    const double x = q[0], th = q[1], xd = u[0], thd = u[1];
    Eigen::Matrix2d A;
    A << M + mp, -mp * l * std::cos(th), -mp * l * std::cos(th), mp * l * l + I;
    const Eigen::Vector2d B(-mp * l * std::sin(th) * thd * thd - k * x - c * xd, -mp * g * l * std::sin(th));
    const Workspace ws = formAt(m, q, u);
    INFO("state " << s);
    CHECK(test::relErr(ws.A, A) <= kClosedForm);
    CHECK(test::relErr(ws.B, B) <= kClosedForm);
  }
}

TEST_CASE("a bead sliding on a turning rod: Coriolis and centripetal terms in closed form", "[closedform][sliding]") {
  // Rod (inertia I_z about its CM, CM at a from the z axis) turning by t; a
  // bead (m, J_z) slides along the rod's x by r, at rho = a + r from the axis:
  // A = diag(I_z + m_r a^2 + m rho^2 + J_z, m), B = (-2 m rho r' t', m rho t'^2).
  const double m_r = 1.0, a = 0.5, Iz = 0.1, mb = 0.3, Jz = 0.003;
  SceneSpec s;
  s.name = "bead";
  BodySpec rod = body("rod", "ground", m_r, Vec3(0.01, 0.1, Iz).asDiagonal(), JointType::Revolute);
  rod.joint.axis[0] = Vec3::UnitZ();
  rod.joint.in_body = Vec3(-a, 0, 0);
  BodySpec bead = body("bead", "rod", mb, Vec3(0.001, 0.002, Jz).asDiagonal(), JointType::Prismatic);
  bead.joint.axis[0] = Vec3::UnitX();
  s.bodies = {rod, bead};
  const Model m = buildModel(s);
  double coriolis = 0;
  checkAgainstClosedForm(
      m, 12,
      [&](const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
        const double rho = a + q[1], thd = u[0], rd = u[1];
        const Eigen::Matrix2d A = Eigen::Vector2d(Iz + m_r * a * a + mb * rho * rho + Jz, mb).asDiagonal();
        return std::pair<Eigen::MatrixXd, Eigen::VectorXd>{A, Eigen::Vector2d(-2 * mb * rho * rd * thd, mb * rho * thd * thd)};
      },
      [&](const Workspace&, const Eigen::VectorXd& B) { coriolis = std::max(coriolis, std::abs(B[0])); });
  CHECK(coriolis > 0.1);  // not vacuous: the Coriolis term is there
}

TEST_CASE("a telescoping rod on a turntable: the slide's joint force tau in closed form", "[closedform][sliding]") {
  // Issue 41: the bead's tau is 0 (its parent turns about a fixed axis). Here a
  // yoke turns about z by psi, a rod on it tilts about the yoke's x by theta, and
  // a slider (m, isotropic j) moves along the rod's z by r: spherical coordinates,
  // so the rod's own turning makes phi, and the slide's tau, non-zero. With rod
  // inertia I E and yoke c about z (both CMs on the joint points):
  //   A = diag(c + I + j + m r^2 s^2, I + j + m r^2, m),  s = sin theta, co = cos theta,
  //   B = (-(2 m r r' s^2 + 2 m r^2 s co theta') psi', -2 m r r' theta' + m r^2 psi'^2 s co + m g r s,
  //        m r (theta'^2 + psi'^2 s^2) - m g co)   (Lagrange, V = m g r co).
  const double c = 0.2, I = 0.05, m_s = 0.7, j = 0.004, g = 9.81;
  SceneSpec sc;
  sc.name = "telescope";
  BodySpec yoke = body("yoke", "ground", 1.0, Vec3(0.3, 0.3, c).asDiagonal(), JointType::Revolute);
  yoke.joint.axis[0] = Vec3::UnitZ();
  BodySpec rod = body("rod", "yoke", 0.5, I * Mat3::Identity(), JointType::Revolute);
  rod.joint.axis[0] = Vec3::UnitX();
  BodySpec slider = body("slider", "rod", m_s, j * Mat3::Identity(), JointType::Prismatic);
  slider.joint.axis[0] = Vec3::UnitZ();
  sc.bodies = {yoke, rod, slider};
  const Model m = buildModel(sc);
  double tau = 0;
  checkAgainstClosedForm(
      m, 41,
      [&](const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
        const double th = q[1], r = q[2], ps_d = u[0], th_d = u[1], r_d = u[2], sn = std::sin(th), co = std::cos(th);
        const Eigen::Vector3d A(c + I + j + m_s * r * r * sn * sn, I + j + m_s * r * r, m_s);
        const Eigen::Vector3d B(-(2 * m_s * r * r_d * sn * sn + 2 * m_s * r * r * sn * co * th_d) * ps_d,
                                -2 * m_s * r * r_d * th_d + m_s * r * r * ps_d * ps_d * sn * co + m_s * g * r * sn,
                                m_s * r * (th_d * th_d + ps_d * ps_d * sn * sn) - m_s * g * co);
        return std::pair<Eigen::MatrixXd, Eigen::VectorXd>{Eigen::Matrix3d(A.asDiagonal()), B};
      },
      [&](const Workspace& ws, const Eigen::VectorXd&) { tau = std::max(tau, ws.tau[m.file_to_internal[2]].norm()); });
  CHECK(tau > 0.1);  // not vacuous: the slide's joint point has a velocity-product acceleration
}

TEST_CASE("a prismatic joint along a tilted axis under gravity falls in closed form, every method", "[closedform][sliding]") {
  // x(t) = x0 + v0 t + (g . e) t^2 / 2 along the unit axis e: rk4 integrates a
  // quadratic exactly, so what remains is round-off.
  SceneSpec s;
  s.name = "fall";
  BodySpec b = body("slider", "ground", 1.5, Vec3(0.1, 0.2, 0.25).asDiagonal(), JointType::Prismatic);
  b.joint.axis[0] = Vec3(1, 0, 1).normalized();
  b.joint.in_body = Vec3(0.1, 0, 0.2);
  b.joint.q0[0] = 0.3;
  b.joint.u0[0] = 1.2;
  s.bodies = {b};
  const Model m = buildModel(s);
  const double acc = m.gravity.dot(b.joint.axis[0]);
  for (Method method : inhouseMethods()) {
    const Trajectory tr = simulate(m, checked(test::runSpec(method, Integrator::RK4, 1.0, 1e-3, 0.1)));
    REQUIRE_FALSE(tr.failed());
    for (size_t k = 0; k < tr.size(); ++k) {
      const double t = tr.t[k];
      INFO(methodName(method) << " t " << t);
      CHECK(std::abs(tr.q[k][0] - (0.3 + 1.2 * t + 0.5 * acc * t * t)) <= 1e-12);
      CHECK(std::abs(tr.u[k][0] - (1.2 + acc * t)) <= 1e-12);
    }
  }
}

TEST_CASE("a free body in zero gravity keeps its momenta, every method (rk8pd, 10 s)", "[conservation][sliding]") {
  // p = sum m v and H about the origin are invariants of the exact motion;
  // rk8pd at tol 1e-14 holds them to its own error (measured: p within 9e-15,
  // H within 1.7e-13; at tol 1e-13 the uncorrected eigen method's H drifts 1.8e-12).
  const Model m = freeTop();
  for (Method method : inhouseMethods()) {
    const Trajectory tr = simulate(m, checked(test::runSpec(method, Integrator::RK8PD, 10.0, 1e-14, 0.1)));
    REQUIRE_FALSE(tr.failed());
    const auto [dp, dH] = test::momentumDrift(m, tr);
    INFO(methodName(method) << ": |dp|/|p| " << dp << ", |dH|/|H| " << dH);
    CHECK(dp <= 1e-12);
    CHECK(dH <= 1e-12);
  }
}

TEST_CASE("a torque-free asymmetric top on a free joint follows Euler's equations", "[closedform][sliding]") {
  // Oracle: J w_b' = -w_b x J w_b in the body frame, integrated here by a
  // plain rk4 at 1e-4 s (error ~1e-14 over 10 s), against w_b = R^T w of the
  // in-house run (classical, rk8pd 1e-13). The CM moves at constant velocity.
  const Model m = freeTop();
  const Mat3 J = m.bodies[0].J;
  const Mat3 Jinv = J.inverse();
  auto euler = [&](const Vec3& w) -> Vec3 { return Jinv * Vec3(-w.cross(J * w)); };
  const Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 10.0, 1e-13, 0.5)));
  REQUIRE_FALSE(tr.failed());
  const Vec4 quat0 = m.bodies[0].joint.q0.tail<4>();
  Vec3 w = quatToMatrix(quat0).transpose() * Vec3(m.bodies[0].joint.u0.tail<3>());
  const double h = 1e-4;
  double t = 0;
  Eigen::VectorXd q, u;
  test::internalState(m, tr, 0, q, u);
  const test::Momenta start = test::momenta(m, q, u);
  for (size_t k = 0; k < tr.size(); ++k) {
    while (t < tr.t[k] - h / 2) {
      const Vec3 k1 = euler(w), k2 = euler(w + h / 2 * k1), k3 = euler(w + h / 2 * k2), k4 = euler(w + h * k3);
      w += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      t += h;
    }
    test::internalState(m, tr, k, q, u);
    const Vec3 w_b = quatToMatrix(q.tail<4>()).transpose() * u.tail<3>();
    INFO("t " << tr.t[k] << ": " << w_b.transpose() << " vs Euler " << w.transpose());
    CHECK((w_b - w).norm() <= 1e-10 * w.norm());
    const test::Momenta now = test::momenta(m, q, u);
    CHECK((now.cm - (start.cm + start.p / start.mass * tr.t[k])).norm() <= 1e-11);
  }
}

TEST_CASE("Solo 12 freed by --floating-base in zero gravity: momenta kept, CM on a straight line", "[conservation][sliding][urdf]") {
  UrdfOptions opt;
  opt.floating_base = true;
  Model m = loadScene(test::sourcePath("data/robots/solo12.urdf"), opt).model;
  REQUIRE(m.nu == 18);
  REQUIRE(m.bodies[0].joint.type == JointType::Free);
  m.gravity.setZero();
  m.has_gravity = false;
  std::mt19937 rng(5);
  Eigen::VectorXd q, u;
  randomState(m, rng, q, u);  // every joint moving, the base tumbling and drifting
  for (const Body& b : m.bodies) {
    m.bodies[&b - m.bodies.data()].joint.q0 = q.segment(b.iq, b.nq());
    m.bodies[&b - m.bodies.data()].joint.u0 = u.segment(b.iu, b.nu());
  }
  const Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 2.0, 1e-13, 0.05)));
  REQUIRE_FALSE(tr.failed());
  const auto [dp, dH] = test::momentumDrift(m, tr);
  INFO("|dp|/|p| " << dp << ", |dH|/|H| " << dH);
  CHECK(dp <= 1e-11);
  CHECK(dH <= 1e-11);
  test::internalState(m, tr, 0, q, u);
  const test::Momenta start = test::momenta(m, q, u);
  for (size_t k = 0; k < tr.size(); ++k) {
    test::internalState(m, tr, k, q, u);
    CHECK((test::momenta(m, q, u).cm - (start.cm + start.p / start.mass * tr.t[k])).norm() <= 1e-11);
  }
}
