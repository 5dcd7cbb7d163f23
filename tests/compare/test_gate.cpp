// The gate: the project's tolerance file loads; a tightened one breaks; run
// settings, failures and short runs are caught; bad files name the key.
#include <catch2/catch.hpp>

#include <fstream>

#include "compare/gate.hpp"
#include "engines.hpp"
#include "support.hpp"
#include "synthetic.hpp"

using namespace em;
using json = nlohmann::json;

namespace {

std::string writeTemp(const std::string& name, const json& j) {
  const std::string path = std::string(EM_BINARY_DIR) + "/" + name;
  std::ofstream(path) << j.dump(1);
  return path;
}

json tolerances(double pose_bound, const std::string& integrator = "rk4") {
  return {{"format", "eigenmass-tolerances/1"},
          {"scenes",
           {{"synthetic",
             {{"horizon_s", 2.0},
              {"inhouse", integrator == "rk4" ? json{{"integrator", integrator}, {"dt", 1e-3}}
                                              : json{{"integrator", integrator}, {"tolerance", 1e-10}}},
              {"methods",
               {{"classical", {{"max_pose_error_rad", {{"value", pose_bound}, {"reason", "test bound"}}}}},
                {"eigen-jacobi-orth", {{"energy_error_max", {{"value", 1.0}, {"reason", "skipped"}}}}}}}}}}}};
}

ComparisonResult synthetic(Trajectory run) {
  CompareOptions o;
  ComparisonResult r = compareTrajectories(test::turning(em::test::method("simbody"), 0, 0), test::turning(em::test::method("simbody"), 0, 0), {run}, o);
  r.scene_name = "synthetic";
  return r;
}

}  // namespace

TEST_CASE("the project's tolerance file loads with a reason for every bound", "[gate]") {
  const Tolerances t = loadTolerances(test::sourcePath("data/tolerances.json"));
  REQUIRE(t.scenes.count("pendulum5"));
  CHECK(t.scenes.at("pendulum5").horizon_s <= 3.0);
  for (const auto& [scene, st] : t.scenes)
    for (const auto& [method, bounds] : st.methods)
      for (const Bound& b : bounds) CHECK_FALSE(b.reason.empty());
}

TEST_CASE("a bound above the measured error passes and a tightened one breaks", "[gate]") {
  // classical's pose error grows as 1e-3 t: 2e-3 rad at the 2 s horizon, 1e-2 by 10 s.
  const ComparisonResult r = synthetic(test::turning(Method::Classical, 1e-3, 0));
  const GateResult ok = evaluateGate(r, loadTolerances(writeTemp("tol_ok.json", tolerances(2.5e-3))));
  CHECK(ok.passed);
  REQUIRE(ok.checks.size() == 1);  // eigen-jacobi-orth did not run: skipped
  CHECK(ok.checks[0].value == Approx(2e-3).epsilon(1e-9));
  const GateResult broken = evaluateGate(r, loadTolerances(writeTemp("tol_tight.json", tolerances(1.5e-3))));
  CHECK_FALSE(broken.passed);
  CHECK_THAT(brokenChecks(broken), Catch::Contains("gate broken: classical max_pose_error_rad"));
}

TEST_CASE("other run settings, a failure or a short run break the bounds", "[gate]") {
  const Trajectory good = test::turning(Method::Classical, 1e-4, 0);
  const GateResult other = evaluateGate(synthetic(good), loadTolerances(writeTemp("tol_rk8.json", tolerances(1, "rk8pd"))));
  CHECK_FALSE(other.passed);
  CHECK_THAT(other.checks[0].note, Catch::Contains("other in-house integrator settings"));
  Trajectory failed = test::turning(Method::Classical, 1e-4, 0, 1.0);
  markFailed(failed, 1.0, Failure::BlowUp, "blow-up");
  const Tolerances t = loadTolerances(writeTemp("tol_one.json", tolerances(1)));
  CHECK_THAT(evaluateGate(synthetic(failed), t).checks[0].note, Catch::Contains("failed at t = 1 s: blow-up"));
  const Trajectory shorter = test::turning(Method::Classical, 1e-4, 0, 1.0);
  CHECK_THAT(evaluateGate(synthetic(shorter), t).checks[0].note, Catch::Contains("shorter than the horizon"));
  ComparisonResult unknown = synthetic(good);
  unknown.scene_name = "elsewhere";
  CHECK_FALSE(evaluateGate(unknown, t).passed);
}

TEST_CASE("a malformed tolerance file names the file and the key", "[gate]") {
  json j = tolerances(1);
  j["scenes"]["synthetic"]["methods"]["classical"]["max_pose_error_rad"].erase("reason");
  const std::string p = writeTemp("tol_bad.json", j);
  CHECK_THROWS_WITH(loadTolerances(p), p + ": scenes.synthetic.methods.classical.max_pose_error_rad.reason: every bound needs a one-line reason");
  j = tolerances(1);
  j["scenes"]["synthetic"]["methods"]["classical"]["max_angle"] = {{"value", 1}, {"reason", "x"}};
  CHECK_THROWS_WITH(loadTolerances(writeTemp("tol_bad2.json", j)), Catch::Contains("methods.classical.max_angle: unknown metric"));
  // Method and integrator names are the registry's.
  j = tolerances(1);
  j["scenes"]["synthetic"]["methods"]["newton"] = j["scenes"]["synthetic"]["methods"]["classical"];
  CHECK_THROWS_WITH(loadTolerances(writeTemp("tol_bad3.json", j)), Catch::Contains("methods.newton: unknown method"));
  CHECK_THROWS_WITH(loadTolerances(writeTemp("tol_bad4.json", tolerances(1, "rkmerson"))),
                    Catch::Contains("synthetic.inhouse.integrator: unknown in-house integrator 'rkmerson'"));
  // A setting the integrator does not read, a duplicate key (the file is read strictly), a key of nobody's.
  j = tolerances(1);
  j["scenes"]["synthetic"]["inhouse"]["tolerance"] = 1e-10;
  CHECK_THROWS_WITH(loadTolerances(writeTemp("tol_bad5.json", j)), Catch::Contains("synthetic.inhouse.tolerance: rk4 takes dt, not tolerance"));
  const std::string dup = std::string(EM_BINARY_DIR) + "/tol_bad6.json";
  std::ofstream(dup) << R"({"format": "eigenmass-tolerances/1", "format": "eigenmass-tolerances/1", "scenes": {}})";
  CHECK_THROWS_WITH(loadTolerances(dup), Catch::Contains("tol_bad6.json") && Catch::Contains("format") && Catch::Contains("duplicate"));
  j = tolerances(1);
  j["scenes"]["synthetic"]["horizon"] = 2;
  CHECK_THROWS_WITH(loadTolerances(writeTemp("tol_bad7.json", j)), Catch::Contains("scenes.synthetic.horizon: unknown key (horizon_s, inhouse, methods)"));
}

TEST_CASE("a mechanism's loops are gated: a run whose loops open beyond the bound breaks it, a tree's is no measure", "[gate]") {
  json t = tolerances(1.0);
  t["scenes"]["synthetic"]["methods"]["classical"]["max_loop_violation"] = {{"value", 1e-9}, {"reason", "test bound"}};
  const Tolerances tol = loadTolerances(writeTemp("tol_loops.json", t));
  ComparisonResult r = synthetic(test::turning(Method::Classical, 1e-4, 0));
  r.metrics[0].has_loops = true;
  r.metrics[0].loops.position_m = 4e-10;
  r.metrics[0].loops.position_rad = 2e-10;
  const GateResult shut = evaluateGate(r, tol);
  CHECK(shut.passed);
  r.metrics[0].loops.position_rad = 3e-9;  // the angular rows open: m or rad, the larger
  const GateResult open = evaluateGate(r, tol);
  CHECK_FALSE(open.passed);
  CHECK_THAT(brokenChecks(open), Catch::Contains("classical max_loop_violation"));
  r.metrics[0].has_loops = false;  // a bound on loops for a run without them is not silently met
  const GateResult none = evaluateGate(r, tol);
  CHECK_FALSE(none.passed);
  CHECK_THAT(brokenChecks(none), Catch::Contains("no loops measured"));
}
