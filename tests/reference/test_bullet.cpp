// Bullet as an engine (reference/bullet.cpp): its u' under the
// in-house rk4 integrates the same ODE as classical rk4, so the two agree to
// round-off until chaos amplifies it, on every joint kind (a free joint as
// the floating base and inside a tree); stepSimulation's semi-implicit Euler
// is first order and btMultiBody's own rk4 fourth order on revolute joints,
// second with a spherical one, first with a floating base (as measured here);
// on a free body in zero gravity its stepping keeps momenta as measured here
// (Erez, Tassa and Todorov 2015's test); its energy balance closes on damped
// scenes at its order.
#include <catch2/catch.hpp>

#include <tuple>

#include "compare/engines.hpp"
#include "engines.hpp"
#include "momenta.hpp"
#include "support.hpp"

using namespace em;

namespace {

// The largest pose error against the reference over 0.5 s at dt and dt/2.
std::pair<double, double> halvedErrors(const Model& m, const Trajectory& ref, const char* scheme, double dt, int evals) {
  double err[2];
  for (int i = 0; i < 2; ++i) {
    const Trajectory b = runTrajectory(m, checked(test::runSpec(test::method("bullet"), test::scheme(scheme), 0.5, dt / (1 + i))));
    REQUIRE_FALSE(b.failed());
    CHECK(b.rhs_evals == evals * b.steps);
    err[i] = test::stateDiff(b, ref, 0.5);
  }
  return {err[0], err[1]};
}

}  // namespace

TEST_CASE("Bullet's u' under the in-house rk4 agrees with classical rk4 to round-off over the first second", "[crosscheck][bullet]") {
  // The same A and B (crosscheck: 1e-14), the same tableau, the same step:
  // what differs is round-off, amplified by the motion. Measured over 1 s at
  // dt 1e-3 on scenes of every joint kind and random trees of every kind
  // (free joints inside the tree: prismatic links and a spherical one) and a
  // free top: at most 2.1e-13; 1e-10 leaves room for other machines and
  // chaos, 1e4 below a wrong term.
  std::vector<Model> models = test::modelsOfEveryKind();
  models.push_back(test::freeTop());
  const Method udot = test::method("bullet-udot");
  for (const Model& m : models) {
    const Trajectory in = runTrajectory(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 1e-3)));
    const Trajectory bullet = runTrajectory(m, checked(test::runSpec(udot, Integrator::RK4, 1.0, 1e-3)));
    REQUIRE_FALSE(in.failed());
    REQUIRE_FALSE(bullet.failed());
    INFO(m.name << ": max |dq|, |du| over 1 s " << test::stateDiff(in, bullet, 1.0));
    CHECK(test::stateDiff(in, bullet, 1.0) <= 1e-10);
    CHECK(test::maxPoseDiff(in, bullet) <= 1e-10);
  }
}

TEST_CASE("Bullet's stepping is first order, its rk4 fourth order on revolute joints, second with a spherical one, first with a floating base", "[bullet]") {
  // Halving dt divides the error by 2^order (1.6 to 2.4 asserted for 2, 3.2
  // to 4.8 for 4, 12.8 to 19.2 for 16). btMultiBody's rk4 (Bullet 3.24):
  // stepPositionsMultiDof updates the link caches at each stage's positions,
  // so revolute (and prismatic) links take every stage where it is and the
  // scheme is fourth order there; a spherical link (our ball and gimbal, a
  // free joint's turning) is advanced by the stages' averaged angular velocity
  // as one rotation, second order; a floating base's orientation stays at the
  // step's start, first order. Measured over 0.5 s at dt / dt/2 (pose error
  // against Simbody at 1e-12): ur5 (six revolutes) rk4 3.3e-7 / 2.0e-8 / 1.3e-9
  // at 5e-3 / 2.5e-3 / 1.25e-3 (16.2x, 16.1x); pendulum5 (a gimbal root, four
  // revolutes) euler 0.23 / 0.12 rad, rk4 1.2e-6 / 3.0e-7 at 1e-3 / 5e-4;
  // tree_mixed (ball, gimbal, universal, revolute) rk4 3.1e-5 / 7.8e-6;
  // floating_arm rk4 6.1e-5 / 3.0e-5. (This comment said second order on a
  // fixed base until an audit measured the ur5: the pendulum's gimbal root
  // had made it so.) Four rk4 stages and a fifth forward dynamics at the start
  // state are five evaluations a step.
  struct Case {
    const char* path;
    double dt, rk4_ratio;
  };
  for (const Case& c : {Case{"data/robots/ur5.urdf", 2e-3, 16}, Case{"data/scenes/pendulum5.json", 1e-3, 4},
                        Case{"data/scenes/tree_mixed.json", 1e-3, 4}, Case{"data/scenes/floating_arm.json", 1e-3, 2}}) {
    const Model m = loadScene(test::sourcePath(c.path)).model;
    const Trajectory ref = runTrajectory(m, checked(test::runSpec(test::method("simbody"), test::scheme("rkmerson"), 0.5, 1e-12)));
    const auto [e1, e2] = halvedErrors(m, ref, "bullet-euler", c.dt, 1);
    INFO(c.path << " euler: " << e1 << " at " << c.dt << ", " << e2 << " at half");
    CHECK(e1 > 1.6 * e2);
    CHECK(e1 < 2.4 * e2);
    const auto [r1, r2] = halvedErrors(m, ref, "bullet-rk4", c.dt, 5);
    INFO(c.path << " rk4: " << r1 << " at " << c.dt << ", " << r2 << " at half");
    CHECK(r1 > 0.8 * c.rk4_ratio * r2);
    CHECK(r1 < 1.2 * c.rk4_ratio * r2);
  }
}

TEST_CASE("Bullet's stepping on a free body in zero gravity: momenta drift at its order", "[conservation][bullet]") {
  // Erez et al.'s test: p and H about the origin are invariants. Bullet's
  // floating base moves its CM at v_CM and turns by the exponential map; its
  // world-frame [w, v_CM] change only through the gyroscopic term. Measured
  // over 10 s (dt 1e-3 / 5e-4): p is kept to round-off (a force-free CM
  // moves straight, |dp|/|p| 1e-15), H drifts 4.8e-3 / 2.4e-3 under euler
  // and 8.2e-3 / 4.1e-3 under rk4 (both first order with a floating base).
  const Model m = test::freeTop();
  for (const char* scheme : {"bullet-euler", "bullet-rk4"}) {
    double dp[2], dH[2];
    for (int i = 0; i < 2; ++i) {
      const Trajectory b = runTrajectory(m, checked(test::runSpec(test::method("bullet"), test::scheme(scheme), 10.0, i == 0 ? 1e-3 : 5e-4, 0.1)));
      REQUIRE_FALSE(b.failed());
      std::tie(dp[i], dH[i]) = test::momentumDrift(m, b);
    }
    INFO(scheme << ": |dp|/|p| " << dp[0] << " -> " << dp[1] << ", |dH|/|H| " << dH[0] << " -> " << dH[1]);
    CHECK(dp[0] <= 1e-12);
    CHECK(dH[0] <= 1e-2);
    CHECK(dH[0] > 1.6 * dH[1]);
  }
}

TEST_CASE("Bullet's stepping closes the energy balance on a damped scene at first order", "[bullet]") {
  // The springs' and dampers' torques are held over a step (Bullet has no
  // joint springs), so both schemes are first order in them; W_diss is the
  // harness's fourth-order sum of c u^2; E includes the springs' potential.
  // Measured over 1 s, |E + W_diss - E(0)| / |E(0)| at dt 1e-3 / 5e-4: euler
  // 8.2e-3 / 4.0e-3, rk4 3.1e-2 / 1.6e-2.
  const Model m = test::loadData("spring_damper.json");
  for (const char* scheme : {"bullet-euler", "bullet-rk4"}) {
    double balance[2];
    for (int i = 0; i < 2; ++i) {
      const Trajectory b = runTrajectory(m, checked(test::runSpec(test::method("bullet"), test::scheme(scheme), 1.0, i == 0 ? 1e-3 : 5e-4)));
      REQUIRE_FALSE(b.failed());
      CHECK(b.dissipated.back() > 1);
      balance[i] = std::abs(b.energy.back() + b.dissipated.back() - b.energy.front()) / std::abs(b.energy.front());
    }
    INFO(scheme << ": balance " << balance[0] << " -> " << balance[1]);
    CHECK(balance[0] <= 0.1);
    CHECK(balance[0] > 1.6 * balance[1]);
  }
}

// Mechanisms in Bullet (reference/bullet.cpp): closures as btMultiBodyPoint2Point
// (a hinge two) and btMultiBodyFixedConstraint, held at the velocity level by
// its solver (ERP 0.2, 10 iterations), handed to it as one group; drives and
// point springs as forces held over a step. Oracle: the in-house motion
// (classical, projection, rk8pd 1e-12). Measured over 0.5 s at dt 1e-4 / 5e-5
// (pose error; loops open, m): door and plate 3.0e-4 / 1.5e-4, 5.5e-7 /
// 1.4e-7; A04 7.1e-5 / 3.6e-5, 3.1e-8 / 7.7e-9; A05 (no loops) 8.3e-5 / 4.2e-5.
// Without the closures handed to the solver (Bullet reaches them only through
// colliders' islands) the loops open by metres.
TEST_CASE("Bullet's closures hold and its mechanisms converge at first order to the in-house motion", "[bullet][mechanism]") {
  test::checkMechanismsFirstOrder("bullet", "bullet-euler");
}
