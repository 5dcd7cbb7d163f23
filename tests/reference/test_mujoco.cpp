// MuJoCo as a trajectory engine (reference/mujoco.cpp): the same
// scheme (rk4) at the same step integrates the same ODE as the in-house
// classical rk4, so the two agree to round-off until chaos amplifies it; at
// a small step MuJoCo agrees with Simbody; its energies and poses are ours.
#include <catch2/catch.hpp>

#include <random>

#include "reference/mujoco.hpp"
#include "reference/simbody.hpp"
#include "solver/integrate.hpp"
#include "engines.hpp"
#include "support.hpp"

using namespace em;

TEST_CASE("MuJoCo rk4 and classical rk4 at the same step agree to round-off over the first second", "[crosscheck][mujoco]") {
  // Same ODE (the same A and B to 1e-15, crosscheck), same tableau, same step:
  // what differs is round-off (~1e-16 per evaluation), amplified by the
  // motion. Measured over 1 s at dt 1e-3: at most 3.5e-13 on the data scenes
  // of hinges and slides, 2e-12 on the random trees; 1e-10 leaves room for
  // other machines' round-off, and is 1e4 below what a wrong term would give.
  std::vector<Model> models;
  for (const char* s : {"pendulum5.json", "chain10.json", "cartpole.json", "spring_damper.json"}) models.push_back(test::loadData(s));
  for (unsigned seed : {1u, 2u, 3u, 4u}) models.push_back(test::randomTree(seed, 6));
  for (const Model& m : models) {
    const Trajectory in = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 1e-3)));
    const Trajectory mj = simulateMujoco(m, checked(test::runSpec(em::test::method("mujoco"), Integrator::RK4, 1.0, 1e-3)));
    REQUIRE_FALSE(in.failed());
    REQUIRE_FALSE(mj.failed());
    REQUIRE(mj.size() == in.size());
    INFO(m.name << ": max |dq|, |du| over 1 s " << test::stateDiff(in, mj, 1.0));
    CHECK(test::stateDiff(in, mj, 1.0) <= 1e-10);
    // MuJoCo's own energies and poses of the same states are ours.
    for (size_t k = 0; k < in.size(); ++k) CHECK(std::abs(mj.energy[k] - in.energy[k]) <= 1e-10 * std::max(1.0, std::abs(in.energy[k])));
    CHECK(test::maxPoseDiff(in, mj) <= 1e-10);
  }
}

TEST_CASE("MuJoCo's u' under the in-house rk4 is MuJoCo's own rk4 on hinges and slides and classical's on every kind", "[crosscheck][mujoco]") {
  // mujoco-udot (mj_forward's qacc under our integrators): on the scenes of
  // hinges and slides MuJoCo's RK4 is the same tableau on the same ODE, so
  // the two agree to round-off (measured at most 3e-13 over 1 s at dt 1e-3;
  // 1e-10 as above). Under rk8pd it is then MuJoCo's dynamics apart from its integrator.
  const Method udot = test::method("mujoco-udot");
  for (const char* s : {"pendulum5.json", "chain10.json", "cartpole.json", "spring_damper.json"}) {
    const Model m = test::loadData(s);
    const Trajectory mj = simulateMujoco(m, checked(test::runSpec(em::test::method("mujoco"), Integrator::RK4, 1.0, 1e-3)));
    const Trajectory ours = simulate(m, checked(test::runSpec(udot, Integrator::RK4, 1.0, 1e-3)));
    REQUIRE_FALSE(ours.failed());
    INFO(s << ": max |dq|, |du| over 1 s " << test::stateDiff(mj, ours, 1.0));
    CHECK(test::stateDiff(mj, ours, 1.0) <= 1e-10);
  }
  // Balls, gimbals, universals, a free root, a planar joint: under the in-house rk4 its u' is
  // classical's, the quaternions integrated alike (MuJoCo's own RK4 would not: second order on a
  // quaternion, below). What remains is MuJoCo's compile-time rounding of the inertias (crosscheck:
  // its raw u' up to 4.7e-8 relative off on planar_sled, 2e-8 on floating_arm; its "-mass" rows
  // 1e-14), grown over 1 s to at most 1.6e-7 (measured: pendulum5_ball below 1e-10, tree_mixed 6.9e-9,
  // floating_arm 9.7e-9, planar_sled 1.6e-7). 1e-6 holds that; a speed in the wrong frame is O(0.1).
  constexpr double kCompiledInertia = 1e-6;
  for (const char* s : {"pendulum5_ball.json", "tree_mixed.json", "floating_arm.json", "planar_sled.json"}) {
    const Model m = test::loadData(s);
    const Trajectory in = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 1e-3)));
    const Trajectory ours = simulate(m, checked(test::runSpec(udot, Integrator::RK4, 1.0, 1e-3)));
    REQUIRE_FALSE(ours.failed());
    INFO(s << ": max |dq|, |du| over 1 s " << test::stateDiff(in, ours, 1.0));
    CHECK(test::stateDiff(in, ours, 1.0) <= kCompiledInertia);
  }
}

TEST_CASE("ball joints: MuJoCo 2.2's RK4 is second order on a quaternion, the in-house rk4 fourth", "[crosscheck][mujoco]") {
  // MuJoCo turns a quaternion by the exponential of a velocity in each stage
  // and of the stages' weighted mean at the end; the in-house rk4 integrates
  // q' = (0, w) q / 2 as any other coordinate and normalizes after the step.
  // Against Simbody (accuracy 1e-12) on pendulum5_ball over 0.1 s, measured:
  // MuJoCo 2.44e-8 at dt 1e-3 and 6.10e-9 at 5e-4 (ratio 4.0: second
  // order), in-house 1.6e-11 and 2.2e-12 (ratio 7.4, at Simbody's own floor).
  const Model m = test::loadData("pendulum5_ball.json");
  const Trajectory sb = SimbodySystem(m).simulate(checked(test::runSpec(em::test::method("simbody"), em::test::scheme("rkmerson"), 0.1, 1e-12)));
  double mj_err[2], in_err[2];
  for (int i = 0; i < 2; ++i) {
    const double dt = i == 0 ? 1e-3 : 5e-4;
    in_err[i] = test::stateDiff(simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 0.1, dt))), sb, 0.1);
    mj_err[i] = test::stateDiff(simulateMujoco(m, checked(test::runSpec(em::test::method("mujoco"), Integrator::RK4, 0.1, dt))), sb, 0.1);
  }
  INFO("MuJoCo " << mj_err[0] << " -> " << mj_err[1] << ", in-house " << in_err[0] << " -> " << in_err[1]);
  CHECK(mj_err[0] / mj_err[1] > 3.5);  // second order: 4
  CHECK(mj_err[0] / mj_err[1] < 5.0);  // not fourth: 16
  CHECK(mj_err[0] < 1e-6);
  CHECK(in_err[0] < 1e-3 * mj_err[0]);
}

TEST_CASE("MuJoCo at a small step agrees with the Simbody reference", "[crosscheck][mujoco]") {
  // Hinges, slides and a slowly turning free base: rk4 at dt 1e-4 errs by
  // ~1e-13 per unit time; Simbody at accuracy 1e-12. Over 1 s both are within
  // 1e-8 rad / m of each other. (Ball joints: the case above.)
  for (const char* s : {"pendulum5.json", "cartpole.json", "floating_arm.json", "spring_damper.json"}) {
    const Model m = test::loadData(s);
    const Trajectory mj = simulateMujoco(m, checked(test::runSpec(em::test::method("mujoco"), Integrator::RK4, 1.0, 1e-4)));
    const Trajectory sb = SimbodySystem(m).simulate(checked(test::runSpec(em::test::method("simbody"), em::test::scheme("rkmerson"), 1.0, 1e-12)));
    REQUIRE_FALSE(mj.failed());
    REQUIRE_FALSE(sb.failed());
    INFO(s << ": pose difference " << test::maxPoseDiff(mj, sb));
    CHECK(test::maxPoseDiff(mj, sb) <= 1e-8);
  }
}

TEST_CASE("MuJoCo's Euler and implicit schemes run, first order, and a damped scene closes its energy balance", "[mujoco]") {
  // Semi-implicit Euler is first order: halving dt halves its error against
  // the Simbody reference (a ratio above 1.6 asserted). The dampers' work is
  // summed per step (c u^2 dt), so E + W_diss stays within O(dt) of E(0).
  const Model m = test::loadData("spring_damper.json");
  const Trajectory sb = SimbodySystem(m).simulate(checked(test::runSpec(em::test::method("simbody"), em::test::scheme("rkmerson"), 1.0, 1e-12)));
  for (Integrator scheme : {em::test::scheme("euler"), em::test::scheme("implicit")}) {
    double err[2];
    for (int i = 0; i < 2; ++i) {
      const Trajectory mj = simulateMujoco(m, checked(test::runSpec(em::test::method("mujoco"), scheme, 1.0, i == 0 ? 1e-3 : 5e-4)));
      REQUIRE_FALSE(mj.failed());
      err[i] = test::stateDiff(mj, sb, 1.0);
      const double balance = std::abs(mj.energy.back() + mj.dissipated.back() - mj.energy.front());
      CHECK(balance <= 0.05 * std::abs(mj.energy.front()));
      CHECK(mj.dissipated.back() > 0);
    }
    INFO(integratorName(scheme) << ": " << err[0] << " at 1e-3, " << err[1] << " at 5e-4");
    CHECK(err[0] > 1.6 * err[1]);
    CHECK(err[0] < 0.1);
  }
}

// A mechanism in MuJoCo (docs/reference-engines.md, "Mechanisms"): loops as
// connect equalities (a hinge two, a weld three), soft at MuJoCo's default
// solref (0.02 s, 1) and solimp (0.9, 0.95, 0.001). The loops then stay open
// by what solref allows, the same at dt 1e-3 and 1e-4 (the soft dynamics are
// resolved by rk4 at both), and E + W_diss drifts by the constraints' own
// damping. Measured over 2 s (max violation in m or rad, max |E + W_diss - E(0)|
// in J): A02 N = 2 5.4e-4, 0.129; A04 1.4e-3, 0.0276; door and plate 8.2e-3,
// 0.304 (it starts away from the zero coordinates). The bars are three times those; a tree (a loop dropped) opens by metres,
// anchors computed at qpos0 by MuJoCo's compiler (eq_data not rewritten) by
// decimetres.
TEST_CASE("MuJoCo closes loops by its soft equalities, open by what solref allows and not by the step", "[mujoco][mechanism]") {
  struct Case {
    const char* file;
    double gap_m, energy;  // bars: m or rad, J
  };
  for (const Case c : {Case{"data/scenes/mechanisms/iftomm_a02_n2.json", 1.6e-3, 0.4}, Case{"data/scenes/mechanisms/iftomm_a04.json", 4e-3, 0.09},
                       Case{"tests/scenes/mechanisms/door_and_plate.json", 2.5e-2, 0.9}}) {
    INFO(c.file);
    const Model m = loadScene(test::sourcePath(c.file)).model;
    double gap[2] = {0, 0};
    for (int i = 0; i < 2; ++i) {
      const double dt = i == 0 ? 1e-3 : 1e-4;
      const Trajectory mj = simulateMujoco(m, checked(test::runSpec(em::test::method("mujoco"), Integrator::RK4, 2.0, dt)));
      REQUIRE(mj.status() == Outcome::Ok);
      REQUIRE(mj.has_loops);
      gap[i] = std::max(mj.loops.position_m, mj.loops.position_rad);
      double drift = 0;
      for (size_t s = 0; s < mj.size(); ++s) {
        drift = std::max(drift, std::abs(mj.energy[s] + mj.dissipated[s] - mj.energy[0]));
      }
      INFO("dt " << dt << ": violation " << gap[i] << ", energy drift " << drift);
      CHECK(gap[i] < c.gap_m);
      CHECK(drift < c.energy);
    }
    CHECK(std::abs(gap[0] - gap[1]) < 0.1 * gap[1]);  // solref's, not the step's
  }
}

// A point spring-damper as MuJoCo's spatial tendon with damping (A05's two,
// k = 8e5 N/m, c = 4e4 N s/m): its work c l'^2 joins W_diss, l'' taken as
// J qacc (MuJoCo gives no rate of the tendon's Jacobian). Oracle: the energy
// balance E + W_diss = E(0). Measured over 1 s with rk4: max |E + W_diss -
// E(0)| 1.7e-7 J at dt 1e-4, 8.6e-9 J at 5e-5 (20-fold: the omitted J' qvel
// leaves W_diss's end correction short of fourth order), of E(0) = 239 J.
TEST_CASE("MuJoCo's point dampers close the energy balance on A05", "[mujoco][mechanism]") {
  const Model m = test::loadData("mechanisms/iftomm_a05.json");
  double balance[2];
  for (int i = 0; i < 2; ++i) {
    const Trajectory mj = simulateMujoco(m, checked(test::runSpec(em::test::method("mujoco"), Integrator::RK4, 1.0, i == 0 ? 1e-4 : 5e-5)));
    REQUIRE(mj.status() == Outcome::Ok);
    CHECK(mj.dissipated.back() > 1e-3);  // the dampers took work
    balance[i] = 0;
    for (size_t s = 0; s < mj.size(); ++s) balance[i] = std::max(balance[i], std::abs(mj.energy[s] + mj.dissipated[s] - mj.energy[0]));
  }
  INFO("balance " << balance[0] << " -> " << balance[1] << " J");
  CHECK(balance[0] < 1e-6);
  CHECK(balance[0] > 8 * balance[1]);
}
