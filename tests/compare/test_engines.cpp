// The runner: one entry point for both engines, equations in file order.
#include <catch2/catch.hpp>

#include "compare/engines.hpp"
#include "engines.hpp"
#include "support.hpp"

using namespace em;

TEST_CASE("in-house and Simbody equations agree in file order on every scene", "[crosscheck][runner]") {
  for (const auto& name : test::dataScenes()) {
    const Model m = test::loadData(name);
    const Equations a = inhouseEquations(m), b = engineEquations(m, em::test::engine("simbody"));
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

TEST_CASE("runTrajectory dispatches to both engines and rejects unknown names", "[runner]") {
  const Model m = test::loadData("chain02.json");
  RunSpec s;
  s.t_end = 0.1;
  s.output_dt = 0.05;
  CHECK(runTrajectory(m, checked(s)).method() == "classical");
  s.method = em::test::method("simbody");
  s.integrator = chosenIntegrator(em::test::engine("simbody"), false);
  const Trajectory t = runTrajectory(m, checked(s));
  CHECK(t.method() == "simbody");
  CHECK(t.integrator() == "rkmerson");
  CHECK(t.size() == 3);
  CHECK_THROWS_WITH(parseMethod("lagrange"), Catch::Contains("unknown method 'lagrange'"));
  CHECK_THROWS_WITH(parseIntegrator("verlet"), Catch::Contains("unknown integrator 'verlet'"));
  s.method = Method::Classical;  // an integrator of the other engine
  CHECK_THROWS_WITH(runTrajectory(m, checked(s)), Catch::Contains("integrator 'rkmerson' is not one of classical's"));
}

TEST_CASE("scene defaults apply where nothing was asked - the reference defaults are one place", "[runner]") {
  const Scene scene = test::sceneData("chain02.json");
  Grid grid;
  CHECK(onGrid(RunSpec(), scene, grid).t_end == scene.t_end);
  grid.output_dt = 0.05;
  const RunSpec s = onGrid(RunSpec(), scene, grid);
  CHECK(s.output_dt == 0.05);
  CHECK(s.t_end == scene.t_end);
  CHECK(defaultReferenceSpec().integrator == em::test::scheme("rkmerson"));
  CHECK(defaultReferenceSpec(Method::Classical).integrator == Integrator::RK8PD);
  CHECK(chosenIntegrator(Engine::InHouse, true) == Integrator::RK8PD);
}
