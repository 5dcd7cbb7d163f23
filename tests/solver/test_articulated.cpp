// The articulated-body method (solver/method_articulated.cpp) against
// classical, an independent route to the same u' (A formed by Wittenburg's
// subtree sums, then Cholesky): at random states of every shipped scene and
// robot and of random trees of all six joint kinds; trajectories under the
// same integrator; closed forms; and its failures.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "solver/dynamics.hpp"
#include "solver/integrate.hpp"
#include "support.hpp"

using namespace em;

namespace {

// u' of `method` at (q, u) through Dynamics::rhs.  // -> (nu)
Eigen::VectorXd udotAt(Dynamics& dyn, const Eigen::VectorXd& q, const Eigen::VectorXd& u, Status* status = nullptr) {
  const Model& m = dyn.model();
  Eigen::VectorXd y = dyn.initialState(q, u), dy(dyn.size());
  const Status s = dyn.rhs(0, y.data(), dy.data());
  if (status) *status = s;
  return dy.segment(m.nq, m.nu);
}

// Both routes solve A u' = B backward-stably: each errs by ~eps cond(A)
// relative to max |u'|. The bound is 1e-12 cond(A); measured, the
// largest ratio err / (eps cond(A)) below is printed by the test.
constexpr double kBoundPerCond = 1e-12;

struct Worst {
  double ratio = 0;  // err / (eps cond(A))
  std::string where;
};

// u' of articulated vs classical at `states` random states of m (seed 7).
void compareAtRandomStates(const Model& m, const std::string& name, int states, Worst& worst) {
  Dynamics art(m, Method::Articulated), cla(m, Method::Classical);
  std::mt19937 rng(7);
  Eigen::VectorXd q(m.nq), u(m.nu);
  for (int k = 0; k < states; ++k) {
    randomState(m, rng, q, u);
    Status s;
    const Eigen::VectorXd ref = udotAt(cla, q, u, &s);
    if (!s) continue;  // classical refuses (a gimbal near its lock): nothing to compare
    const double cond = conditionNumber(cla.workspace().A);
    const Eigen::VectorXd got = udotAt(art, q, u, &s);
    INFO(name << " state " << k << " cond(A) " << cond << " " << s.cause);
    REQUIRE(s);
    const double err = test::relErr(got, ref, 1e-3);
    CHECK(err <= kBoundPerCond * cond);
    const double ratio = err / (2.220446049250313e-16 * cond);
    if (ratio > worst.ratio) worst = {ratio, name};
  }
}

// One body hanging from the ground on a joint of `type` at (q0, u0), its CM
// `in_body` from the joint point (body frame).
Model oneBody(JointType type, double mass, const Vec3& moments, const Vec3& in_body, const Eigen::VectorXd& q0,
              const Eigen::VectorXd& u0, const Vec3& gravity = Vec3(0, 0, -9.81)) {
  SceneSpec s;
  s.name = "one_body";
  s.gravity = gravity;
  BodySpec b;
  b.name = "body";
  b.parent = "ground";
  b.mass = mass;
  b.inertia = moments.asDiagonal();
  b.joint.type = type;
  b.joint.axis[0] = Vec3::UnitX();
  b.joint.in_body = in_body;
  b.joint.q0 = q0;
  b.joint.u0 = u0;
  s.bodies.push_back(b);
  return buildModel(s);
}

std::vector<std::string> robotFiles() {
  std::vector<std::string> files;
  for (const char* dir : {"data/robots", "tests/robots"})
    for (const auto& f : std::filesystem::directory_iterator(test::sourcePath(dir)))
      if (f.path().extension() == ".urdf") files.push_back(f.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

TEST_CASE("articulated u' equals classical's to 1e-12 cond(A) at random states of every shipped scene and robot", "[articulated][identity][urdf]") {
  Worst worst;
  for (const auto& name : test::dataScenes()) compareAtRandomStates(test::loadData(name), name, 20, worst);
  for (const std::string& file : robotFiles())
    for (bool floating : {false, true}) {
      if (floating && file.find("data/robots") == std::string::npos) continue;  // tests/robots: a massless root, a floating joint already
      UrdfOptions opt;
      opt.floating_base = floating;
      opt.balance_inertia = file.find("allegro") != std::string::npos;  // as docs/urdf.md runs it
      compareAtRandomStates(loadScene(file, opt).model, file + (floating ? " --floating-base" : ""), 20, worst);
    }
  WARN("largest err / (eps cond(A)): " << worst.ratio << " (" << worst.where << ")");
  CHECK(worst.ratio > 0);  // the comparison ran
}

TEST_CASE("articulated u' equals classical's on random trees of all six joint kinds", "[articulated][identity]") {
  // Full turned inertias, springs, free and ball joints anywhere in the tree,
  // 3 to 40 bodies: trees neither method was written against.
  Worst worst;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    const Model m = test::randomTree(seed, 3 + static_cast<int>(seed % 8) * 5, true);
    compareAtRandomStates(m, "random tree " + std::to_string(seed), 10, worst);
  }
  WARN("largest err / (eps cond(A)): " << worst.ratio << " (" << worst.where << ")");
}

TEST_CASE("articulated closed forms: a free body falls with g and spins by Euler's equations", "[articulated][closedform]") {
  // One free body, CM at the joint point: v' = g, and
  // J w' = -w x J w (the world-frame Euler equations) for the angular part.
  const Vec3 g(0.3, -1.0, -9.81), moments(0.2, 0.5, 0.6);
  Eigen::VectorXd q0(7), u0(6);
  q0 << 1, 2, 3, Eigen::Vector4d(0.9, 0.1, -0.3, 0.2).normalized();
  u0 << 0.5, -0.2, 0.1, 1.0, -2.0, 0.7;
  const Model m = oneBody(JointType::Free, 2.0, moments, Vec3::Zero(), q0, u0, g);
  Dynamics dyn(m, Method::Articulated);
  const Eigen::VectorXd ud = udotAt(dyn, m.q0(), m.u0());
  const Mat3 R = quatToMatrix(Vec4(q0.segment<4>(3)));
  const Mat3 J = R * Mat3(moments.asDiagonal()) * R.transpose();
  const Vec3 w = u0.tail<3>();
  const Vec3 wdot = -J.inverse() * w.cross(J * w);
  constexpr double kRoundoff = 1e-14;  // a few operations on O(1) numbers
  CHECK((ud.head<3>() - g).norm() <= kRoundoff * g.norm());
  CHECK((ud.tail<3>() - wdot).norm() <= kRoundoff * 10 * wdot.norm());
  CHECK(wdot.norm() > 0.1);  // not vacuous
}

TEST_CASE("articulated closed form: a physical pendulum's angular acceleration", "[articulated][closedform]") {
  // A revolute body with its CM at distance l below the pivot: J_O th'' = -m g l sin th,
  // J_O = J_xx + m l^2 (parallel axes).
  // CM 0.8 m below the pivot at rest, turned 0.7 rad about x at 1.3 rad/s.
  const Model m = oneBody(JointType::Revolute, 1.5, Vec3(0.01, 0.02, 0.03), Vec3(0, 0, 0.8),
                          Eigen::VectorXd::Constant(1, 0.7), Eigen::VectorXd::Constant(1, 1.3));
  Dynamics dyn(m, Method::Articulated);
  const double th = 0.7, l = 0.8, J_O = 0.01 + 1.5 * l * l;
  const double expected = -1.5 * 9.81 * l * std::sin(th) / J_O;
  CHECK(std::abs(udotAt(dyn, m.q0(), m.u0())[0] - expected) <= 1e-14 * std::abs(expected));
}

TEST_CASE("articulated trajectories equal classical's under the same integrator", "[articulated][identity]") {
  // The same ODE, u' equal to ~eps cond(A) per evaluation: what separates the
  // runs is round-off amplified by the motion. Measured over 1 s (rk4 dt
  // 1e-3 and rk8pd 1e-10, whose steps follow error estimates of round-off
  // size): at most 1.6e-11 on these seven scenes; 1e-9 leaves room for other
  // machines and is far below what a wrong term would give (1e-3 over a second).
  constexpr double kSameOde = 1e-9;
  std::vector<std::pair<std::string, Model>> scenes;
  for (const char* s : {"pendulum5.json", "cartpole.json", "floating_arm.json", "tree_mixed.json", "spring_damper.json"})
    scenes.emplace_back(s, test::loadData(s));
  for (unsigned seed : {3u, 11u}) scenes.emplace_back("random tree " + std::to_string(seed), test::randomTree(seed, 8, true));
  double worst = 0;
  for (const auto& [name, m] : scenes)
    for (Integrator integ : {Integrator::RK4, Integrator::RK8PD}) {
      const double setting = integ == Integrator::RK4 ? 1e-3 : 1e-10;
      const Trajectory a = simulate(m, checked(test::runSpec(Method::Articulated, integ, 1.0, setting)));
      const Trajectory c = simulate(m, checked(test::runSpec(Method::Classical, integ, 1.0, setting)));
      INFO(name << " " << integratorName(integ) << " " << a.failure);
      REQUIRE_FALSE(a.failed());
      REQUIRE_FALSE(c.failed());
      REQUIRE(a.size() == c.size());
      double d = 0;
      for (size_t k = 0; k < a.size(); ++k)
        d = std::max({d, (a.q[k] - c.q[k]).cwiseAbs().maxCoeff(), (a.u[k] - c.u[k]).cwiseAbs().maxCoeff()});
      CHECK(d <= kSameOde);
      worst = std::max(worst, d);
    }
  WARN("largest |q - q_classical|, |u - u_classical| over 1 s: " << worst);
}

TEST_CASE("a gimbal at its lock makes the joint's articulated inertia singular: articulated fails with the cause", "[articulated][failure]") {
  const Model m = test::lockedGimbal(M_PI / 2);  // Pi_k loses rank: Delta = Pi^T J Pi is singular
  Dynamics dyn(m, Method::Articulated);
  Eigen::VectorXd y = dyn.initialState(m.q0(), m.u0()), dy(dyn.size());
  const Status st = dyn.rhs(0.25, y.data(), dy.data());
  CHECK_FALSE(st);
  CHECK(st.t == 0.25);
  CHECK(st.kind == Failure::Singular);
  CHECK_THAT(st.cause, Catch::Contains("articulated inertia Delta of body 'link1' (along its joint's speeds) numerically singular"));
  CHECK_THAT(st.cause, Catch::EndsWith("(gimbal lock: body 'link1' q1 = 1.5708 rad)"));
}
