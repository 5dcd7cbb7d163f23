// A trajectory through JSON and back: every sample bit for bit (the sweep's
// reference runs are read back this way by other processes).
#include <catch2/catch.hpp>

#include "io/trajectory_json.hpp"
#include "solver/integrate.hpp"
#include "support.hpp"

using namespace em;

TEST_CASE("a trajectory round-trips through JSON text bit for bit", "[trajectory]") {
  const Model m = test::loadData("tree_mixed.json");
  const RunSpec spec = test::runSpec(Method::Classical, Integrator::RK4, 0.2, 1e-3);
  const Trajectory t = simulate(m, checked(spec));
  const nlohmann::json text = nlohmann::json::parse(trajectoryJson(t).dump());
  const Trajectory back = trajectoryFromJson(text, spec, "test");
  REQUIRE(back.size() == t.size());
  CHECK(back.t == t.t);
  CHECK(back.energy == t.energy);
  CHECK(back.kinetic == t.kinetic);
  CHECK(back.q_names == t.q_names);
  CHECK(back.steps == t.steps);
  for (size_t k = 0; k < t.size(); ++k) {
    CHECK(back.q[k] == t.q[k]);
    CHECK(back.u[k] == t.u[k]);
    for (size_t b = 0; b < t.poses[k].size(); ++b) {
      CHECK(back.poses[k][b].p == t.poses[k][b].p);
      CHECK(back.poses[k][b].quat == t.poses[k][b].quat);
    }
  }
}

TEST_CASE("a JSON that is not a trajectory is refused naming its source", "[trajectory]") {
  nlohmann::json j = trajectoryJson(simulate(test::loadData("pendulum5.json"), checked(test::runSpec(Method::Classical, Integrator::RK4, 0.05, 1e-3))));
  j["q"].erase(0);
  CHECK_THROWS_WITH(trajectoryFromJson(j, RunSpec(), "ref.json"), Catch::Contains("ref.json: sample counts differ"));
  j.erase("t");
  CHECK_THROWS_WITH(trajectoryFromJson(j, RunSpec(), "ref.json"), Catch::Contains("ref.json: not a trajectory"));
}

TEST_CASE("a mechanism's run round-trips how it kept its loops closed", "[trajectory][mechanism]") {
  // A plugin's run comes back from its child process this way: without the
  // loop statistics its report had no violation (found when plugins first ran mechanisms).
  const Model m = test::loadData("mechanisms/iftomm_a04.json");
  const RunSpec spec = test::runSpec(Method::Classical, Integrator::RK4, 0.1, 1e-3);
  const Trajectory t = simulate(m, checked(spec));
  REQUIRE(t.has_loops);
  REQUIRE(t.loops.projections > 0);
  const Trajectory back = trajectoryFromJson(nlohmann::json::parse(trajectoryJson(t).dump()), spec, "test");
  CHECK(back.has_loops);
  CHECK(back.loops.position_m == t.loops.position_m);
  CHECK(back.loops.velocity_rad == t.loops.velocity_rad);
  CHECK(back.loops.rank_min == t.loops.rank_min);
  CHECK(back.loops.projections == t.loops.projections);
  CHECK(back.loops.projection_iterations == t.loops.projection_iterations);
  const Trajectory tree = trajectoryFromJson(trajectoryJson(simulate(test::loadData("pendulum5.json"), checked(spec))), spec, "test");
  CHECK_FALSE(tree.has_loops);
}
