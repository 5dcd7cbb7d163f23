// Work-precision sweeps: errors fall with the step at the method's order; bad
// combinations are refused before any run.
#include <sstream>

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

TEST_CASE("precision under rk4: an engine without rk4 runs its own scheme, and its row says which", "[precision]") {
  // Issue 53 item 13: DART and ODE ran their own schemes under --integrator rk4 and the table did not say so.
  const Scene scene = test::sceneData("chain01.json");
  PrecisionOptions o;
  const Method dart = em::test::method("dart");
  o.methods = {Method::Classical, dart};
  o.settings = {1e-3};
  o.grid.t_end = 0.1;
  const PrecisionResult r = runPrecision(scene, o);
  const std::string own = integratorName(defaultIntegrator(info(dart).engine));
  REQUIRE(own != "rk4");
  std::istringstream table(precisionTable(r));
  std::string line;
  int rows = 0;
  while (std::getline(table, line)) {
    if (line.rfind("classical ", 0) == 0) {
      CHECK(line.find(" rk4 ") != std::string::npos);
      ++rows;
    }
    if (line.rfind("dart ", 0) == 0) {
      CHECK(line.find(" " + own + " ") != std::string::npos);
      ++rows;
    }
  }
  CHECK(rows == 2);
}
