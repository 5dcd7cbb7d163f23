// Work-precision sweeps: errors fall with the step at the method's order; bad
// combinations are refused before any run.
#include <catch2/catch.hpp>

#include "compare/precision.hpp"
#include "engines.hpp"
#include "support.hpp"

using namespace em;

TEST_CASE("a precision sweep: rk4 error falls ~16x per halving and cost doubles", "[precision]") {
  PrecisionOptions o;
  o.methods = {Method::Classical, Method::EigenJacobi};
  o.settings = {1e-2, 5e-3};
  o.grid.t_end = 1.0;
  const PrecisionResult r = runPrecision(test::sceneData("chain03.json"), o);
  REQUIRE(r.points.size() == 4);
  for (int k : {0, 2}) {
    const MethodMetrics &coarse = r.points[k].metrics, &fine = r.points[k + 1].metrics;
    INFO(coarse.name());
    CHECK(coarse.status() == Outcome::Ok);
    // Fourth order: 16x; allow 8x to 32x (pose error is a max over time, not one final value).
    CHECK(coarse.pose.value / fine.pose.value > 8);
    CHECK(coarse.pose.value / fine.pose.value < 32);
    CHECK(fine.rhs_evals == 2 * coarse.rhs_evals);
  }
  const auto j = precisionJson(r);
  CHECK(j["format"] == "eigenmass-precision/1");
  CHECK(j["points"][1]["dt"] == 5e-3);
  CHECK(precisionTable(r).find("eigen-jacobi") != std::string::npos);
}

TEST_CASE("simbody needs tolerances: refused under rk4 before any run", "[precision]") {
  const Scene scene = test::sceneData("chain01.json");
  PrecisionOptions o;
  o.methods = {Method::Classical, em::test::method("simbody")};
  CHECK_THROWS_WITH(runPrecision(scene, o), Catch::Contains("simbody has no fixed-step integrator"));
  o.methods = {Method::Classical};
  o.settings = {1e-3, 0};
  CHECK_THROWS_WITH(runPrecision(scene, o), Catch::Contains("must be > 0"));
}
