// The runner: one entry point for both engines, equations in file order.
#include <catch2/catch.hpp>

#include "compare/runner.hpp"
#include "support.hpp"

using namespace em;

TEST_CASE("in-house and Simbody equations agree in file order on every scene", "[crosscheck][runner]") {
  for (const auto& name : test::dataScenes()) {
    const Model m = test::loadData(name);
    const Equations a = inhouseEquations(m), b = simbodyEquations(m);
    INFO(name);
    CHECK(test::relErr(a.A, b.A) <= 1e-12);
    CHECK(test::relErr(a.eigenvalues, b.eigenvalues) <= 1e-12);
    CHECK(test::relErr(a.udot, b.udot, 1e-3) <= test::udotTolerance(b.A));
  }
}

TEST_CASE("pendulum5 equations: the expected eigenvalues and energy", "[closedform][runner]") {
  const Equations e = inhouseEquations(test::loadData("pendulum5.json"));
  REQUIRE(e.nu == 7);
  const double expected[] = {0.0398, 0.137, 0.259, 1.70, 2.44, 31.7, 50.2};  // issue values, 3 digits
  for (int i = 0; i < 7; ++i) CHECK(e.eigenvalues[i] == Approx(expected[i]).epsilon(5e-3));
  CHECK(e.kinetic + e.potential == Approx(-96.927410600287).epsilon(1e-13));
}

TEST_CASE("runMethod dispatches to both engines and rejects unknown names", "[runner]") {
  const Model m = test::loadData("chain02.json");
  RunSpec s;
  s.t_end = 0.1;
  s.output_dt = 0.05;
  CHECK(runMethod(m, s).method == "classical");
  s.method = "simbody";
  const Trajectory t = runMethod(m, s);
  CHECK(t.method == "simbody");
  CHECK(t.integrator == "rkmerson");
  CHECK(t.size() == 3);
  s.method = "lagrange";
  CHECK_THROWS_WITH(runMethod(m, s), Catch::Contains("unknown method 'lagrange'"));
  s.method = "classical";
  s.integrator = "euler";
  CHECK_THROWS_WITH(runMethod(m, s), Catch::Contains("unknown integrator 'euler'"));
}
