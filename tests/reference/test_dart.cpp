// DART as an engine (reference/dart.cpp): its u' under the in-house
// rk4 integrates the same ODE as classical rk4, so the two agree to
// round-off until chaos amplifies it; World::step is first order; on a free
// body in zero gravity its stepping keeps momenta as measured here (Erez,
// Tassa and Todorov 2015's test); its energy balance closes on damped scenes.
#include <catch2/catch.hpp>

#include <tuple>

#include "compare/engines.hpp"
#include "engines.hpp"
#include "momenta.hpp"
#include "support.hpp"

using namespace em;

TEST_CASE("DART's u' under the in-house rk4 agrees with classical rk4 to round-off over the first second", "[crosscheck][dart]") {
  // The same A and B (crosscheck: 1e-14), the same tableau, the same step:
  // what differs is round-off, amplified by the motion. Measured over 1 s at
  // dt 1e-3 on scenes of every joint kind and random trees of every kind: at
  // most 1.0e-11; 1e-10 leaves room for other machines, 1e4 below a wrong term.
  std::vector<Model> models = test::modelsOfEveryKind();
  const Method udot = test::method("dart-udot");
  for (const Model& m : models) {
    const Trajectory in = runTrajectory(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 1e-3)));
    const Trajectory dart = runTrajectory(m, checked(test::runSpec(udot, Integrator::RK4, 1.0, 1e-3)));
    REQUIRE_FALSE(in.failed());
    REQUIRE_FALSE(dart.failed());
    INFO(m.name << ": max |dq|, |du| over 1 s " << test::stateDiff(in, dart, 1.0));
    CHECK(test::stateDiff(in, dart, 1.0) <= 1e-10);
    CHECK(test::maxPoseDiff(in, dart) <= 1e-10);
  }
}

TEST_CASE("DART's World::step is first order against the reference", "[dart]") {
  // Semi-implicit Euler: halving dt halves the error (ratio 2; 1.6 to 2.4
  // asserted). Measured over 0.5 s on pendulum5: 0.222 rad at 1e-3, 0.112 at
  // 5e-4 (a chaotic pendulum started fast); 0.5 holds it.
  for (const char* s : {"pendulum5.json", "floating_arm.json"}) {
    const Model m = test::loadData(s);
    const Trajectory ref = runTrajectory(m, checked(test::runSpec(test::method("simbody"), test::scheme("rkmerson"), 0.5, 1e-12)));
    double err[2];
    for (int i = 0; i < 2; ++i) {
      const Trajectory d = runTrajectory(m, checked(test::runSpec(test::method("dart"), test::scheme("dart-euler"), 0.5, i == 0 ? 1e-3 : 5e-4)));
      REQUIRE_FALSE(d.failed());
      CHECK(d.rhs_evals == d.steps);  // one forward dynamics per step
      err[i] = test::stateDiff(d, ref, 0.5);
    }
    INFO(s << ": " << err[0] << " at 1e-3, " << err[1] << " at 5e-4");
    CHECK(err[0] > 1.6 * err[1]);
    CHECK(err[0] < 2.4 * err[1]);
    CHECK(err[0] < 0.5);
  }
}

TEST_CASE("DART's World::step on a free body in zero gravity: momenta drift at first order", "[conservation][dart]") {
  // Erez et al.'s test: p and H about the origin are invariants of the
  // motion. DART integrates the body-frame spatial velocity at the joint
  // point by semi-implicit Euler, so neither is kept: measured over 10 s,
  // |dp|/|p| 2.3e-3 and |dH|/|H| 4.2e-2 at dt 1e-3, both halving with dt
  // (first order). The in-house rk8pd keeps both to 1e-12 (test_sliding).
  const Model m = test::freeTop();
  double dp[2], dH[2];
  for (int i = 0; i < 2; ++i) {
    const Trajectory d = runTrajectory(m, checked(test::runSpec(test::method("dart"), test::scheme("dart-euler"), 10.0, i == 0 ? 1e-3 : 5e-4, 0.1)));
    REQUIRE_FALSE(d.failed());
    std::tie(dp[i], dH[i]) = test::momentumDrift(m, d);
  }
  INFO("|dp|/|p| " << dp[0] << " -> " << dp[1] << ", |dH|/|H| " << dH[0] << " -> " << dH[1]);
  CHECK(dp[0] <= 5e-3);
  CHECK(dH[0] <= 0.1);
  CHECK(dp[0] > 1.6 * dp[1]);
  CHECK(dH[0] > 1.6 * dH[1]);
}

TEST_CASE("DART's World::step closes the energy balance on a damped scene to first order", "[dart]") {
  // Its springs and dampers are implicit over the step; W_diss is the
  // harness's fourth-order sum of c u^2. E + W_diss - E(0) is then DART's own
  // first-order error: measured 5.1e-2 of |E(0)| over 1 s at dt 1e-3, halving with dt.
  const Model m = test::loadData("spring_damper.json");
  double balance[2];
  for (int i = 0; i < 2; ++i) {
    const Trajectory d = runTrajectory(m, checked(test::runSpec(test::method("dart"), test::scheme("dart-euler"), 1.0, i == 0 ? 1e-3 : 5e-4)));
    REQUIRE_FALSE(d.failed());
    CHECK(d.dissipated.back() > 1);
    balance[i] = std::abs(d.energy.back() + d.dissipated.back() - d.energy.front()) / std::abs(d.energy.front());
  }
  INFO("balance " << balance[0] << " -> " << balance[1]);
  CHECK(balance[0] <= 0.1);
  CHECK(balance[0] > 1.6 * balance[1]);
}

// Mechanisms in DART (reference/dart.cpp): closures as its BallJointConstraint
// (a hinge two) and WeldJointConstraint, impulses at the velocity level;
// drives as joint forces, point springs as external forces. Oracle: the
// in-house motion (classical, projection, rk8pd 1e-12). Measured over 0.5 s
// at dt 1e-4 / 5e-5 (pose error; loops open, m): door and plate 2.9e-4 /
// 1.5e-4, 1.1e-5 / 2.8e-6; A04 7.1e-5 / 3.6e-5, 8.3e-7 / 2.1e-7; A05 (no
// loops) 8.3e-5 / 4.2e-5.
TEST_CASE("DART's joint constraints close loops and its mechanisms converge at first order to the in-house motion", "[dart][mechanism]") {
  test::checkMechanismsFirstOrder("dart", "dart-euler");
}
