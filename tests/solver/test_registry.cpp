// The registry and the run settings: every row is reachable by its name, the
// properties other parts branch on are the ones each method and integrator
// has, and the settings checks refuse what cannot be run (naming the field).
#include <catch2/catch.hpp>

#include "solver/dynamics.hpp"
#include "solver/run.hpp"
#include "support.hpp"

using namespace em;

TEST_CASE("every method and integrator round-trips through its name - unknown names list the known", "[registry]") {
  for (const MethodInfo& m : methodTable()) {
    CHECK(parseMethod(m.name) == m.id);
    CHECK(&info(m.id) == &m);
    CHECK((m.make != nullptr) == (m.engine == Engine::InHouse));  // in-house methods build their own code
  }
  for (const IntegratorInfo& i : integratorTable()) CHECK(parseIntegrator(i.name) == i.id);
  CHECK(methodNames().size() == methodTable().size());
  CHECK(integratorNames(Engine::InHouse).size() + integratorNames(Engine::Simbody).size() == integratorTable().size());
  CHECK_THROWS_WITH(parseMethod("newton"),
                    "unknown method 'newton' (classical, eigen, eigen-jacobi, eigen-jacobi-orth, eigen-block, eigen-block-jacobi, simbody)");
  CHECK_THROWS_WITH(parseIntegrator("euler"), Catch::Contains("unknown integrator 'euler'") && Catch::Contains("rk8pd"));
}

TEST_CASE("the registry's properties are what each method does", "[registry][dynamics]") {
  // correctsAfterStep and the diagnostics follow the row, and the engines' defaults run on their engine.
  const Model m = test::loadData("pendulum5.json");
  for (const MethodInfo& row : methodTable()) {
    if (row.engine != Engine::InHouse) {
      CHECK_THROWS_AS(Dynamics(m, row.id), std::invalid_argument);
      continue;
    }
    Dynamics dyn(m, row.id);
    INFO(row.name);
    // eigen-block carries C and a full D, and re-clusters after every step whatever its correction.
    const bool block = row.make == makeEigenBlock;
    CHECK(dyn.correctsAfterStep() == (block || row.correction != Correction::None));
    CHECK(dyn.eigenfactor() == row.eigenfactor);
    const int extra = block ? 2 * m.nu * m.nu : row.eigenfactor ? m.nu * m.nu + m.nu : 0;
    CHECK(dyn.size() == m.nq + m.nu + extra);
  }
  for (Engine e : {Engine::InHouse, Engine::Simbody}) CHECK(info(defaultIntegrator(e)).engine == e);
  CHECK_THROWS_WITH(requireCompatible(Method::Simbody, Integrator::RK4), Catch::Contains("rk4") && Catch::Contains("simbody"));
  CHECK_THROWS_AS(requireCompatible(Method::Classical, Integrator::CPodes), std::invalid_argument);
  CHECK_NOTHROW(requireCompatible(Method::Classical, Integrator::BSIMP));
}

TEST_CASE("run settings: whole multiples within round-off - bad values name their field", "[registry][integrate]") {
  CHECK(outputIntervals(10.0, 0.01) == 1000);
  CHECK(outputIntervals(0.3, 0.1) == 3);                 // 0.3 / 0.1 = 2.9999999999999996
  CHECK(stepsPerOutput(0.01, 1e-12) == 10000000000L);   // beyond int: no overflow
  CHECK_THROWS_WITH(stepsPerOutput(0.01, 0.003), Catch::Contains("output_dt must be a whole multiple of dt"));
  CHECK_THROWS_WITH(outputIntervals(1.0, 0.3), Catch::StartsWith("t_end 1 must be a whole multiple of output_dt 0.3"));
  RunSpec s;
  for (double bad : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    s.t_end = bad;
    try {
      checkRunSpec(s);
      FAIL("t_end " << bad << " accepted");
    } catch (const SettingError& e) {
      CHECK(e.field == "t_end");
    }
  }
}
