// The engine seam (reference/table.cpp): every row is in the
// registry as an engine, a method and its schemes; every row runs a scene on
// the grid through the one dispatch point and lands near the in-house
// solution; every row that gives equations gives the in-house ones. A new
// engine's row is walked by these tests as it is added.
#include <catch2/catch.hpp>

#include "compare/engines.hpp"
#include "engines.hpp"
#include "support.hpp"

using namespace em;

TEST_CASE("every engine row is in the registry: its engine, its method and its schemes", "[engine]") {
  useEngines();
  useEngines();  // once: a second call adds nothing
  REQUIRE(otherEngines().size() == engineRows().size());
  int references = 0, seconds = 0;
  for (const EngineRow& row : engineRows()) {
    INFO(row.info.name);
    const Engine e = parseEngine(row.info.name);
    const MethodInfo& m = info(info(e).method);
    CHECK(std::string(m.name) == row.info.name);  // an engine runs one method, named as the engine
    CHECK(m.engine == e);
    CHECK(m.make == nullptr);
    CHECK(methodOwner(m.id) == row.info.name);
    CHECK(integratorNames(e).size() == row.info.schemes.size());
    for (const EngineScheme& s : row.info.schemes) {
      CHECK(info(parseIntegrator(s.name)).runs(e));
      CHECK(info(parseIntegrator(s.name)).fixed_step == s.fixed_step);
    }
    CHECK(integratorName(defaultIntegrator(e)) == std::string(row.info.fixed_scheme));
    CHECK(integratorName(adaptiveIntegrator(e)) == std::string(row.info.adaptive_scheme));
    CHECK(&engineCode(e) == &row.code);  // found by its id, not by its name
    CHECK_FALSE(row.code.version().empty());
    references += row.info.roles.reference;
    seconds += row.info.roles.second_scheme != nullptr;
    if (row.info.roles.second_scheme) CHECK(info(parseIntegrator(row.info.roles.second_scheme)).runs(e));
  }
  CHECK(references == 1);  // one default reference and one second engine, each stated on its row
  CHECK(seconds == 1);
  CHECK(referenceEngine() != secondEngine());
  CHECK(info(referenceMethod()).engine == referenceEngine());
  // One name, one scheme: MuJoCo's rk4 is the in-house row.
  CHECK(info(Integrator::RK4).runs(test::engine("mujoco")));
  CHECK(integratorNames(test::engine("mujoco")) == std::vector<std::string>{"rk4", "euler", "implicit"});
  CHECK(info(test::engine("simbody")).max_tol == 1.0);  // Simbody asserts on an accuracy >= 1
}

TEST_CASE("every engine runs a scene on the grid through the one dispatch point, near the in-house solution", "[engine]") {
  // chain02 over 0.1 s at the default scheme, step 1e-4 (adaptive: tolerance
  // 1e-8). The in-house rk8pd at 1e-12 is the truth to ~1e-11. A first-order
  // scheme errs by ~dt T max|u''| ~ 1e-4 * 0.1 * 20 = 2e-4 rad; 1e-3 holds it
  // and is far below a wrong model (a missing term moves q by > 1e-2 here).
  const Scene scene = test::sceneData("chain02.json");
  const Trajectory truth = runTrajectory(scene.model, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 0.1, 1e-12)));
  for (Engine e : otherEngines()) {
    INFO(engineName(e));
    const RunSpec spec = test::runSpec(info(e).method, defaultIntegrator(e), 0.1, info(defaultIntegrator(e)).fixed_step ? 1e-4 : 1e-8);
    const Trajectory tr = runTrajectory(scene.model, checked(spec));
    REQUIRE(tr.status() == Outcome::Ok);
    REQUIRE(tr.size() == truth.size());
    CHECK(tr.q_names == truth.q_names);
    CHECK(tr.steps > 0);
    CHECK(tr.rhs_evals >= tr.steps);
    double err = 0;
    for (size_t k = 0; k < tr.size(); ++k) err = std::max(err, (tr.q[k] - truth.q[k]).cwiseAbs().maxCoeff());
    INFO("max |q - q_truth| " << err);
    CHECK(err < 1e-3);
  }
}

TEST_CASE("every engine that gives equations gives the in-house A, B and u' at the initial state", "[engine][crosscheck]") {
  // Simbody and DART to ~1e-15 relative; MuJoCo on a scene of diagonal
  // inertias (no diagonalization rounding) to the same: 1e-12 holds them with room.
  const Model m = test::loadData("pendulum5.json");
  const Equations in = inhouseEquations(m);
  const std::vector<Engine> engines = enginesWithEquations();
  CHECK(engines.front() == Engine::InHouse);
  size_t with_model = 0;
  for (const EngineRow& r : engineRows()) with_model += r.code.model != nullptr;
  CHECK(engines.size() == 1 + with_model);
  CHECK(with_model >= 3);  // Simbody, MuJoCo and DART at least
  for (Engine e : engines) {
    INFO(engineName(e));
    const Equations q = engineEquations(m, e);
    CHECK((q.A - in.A).cwiseAbs().maxCoeff() <= 1e-12 * in.A.cwiseAbs().maxCoeff());
    CHECK((q.B - in.B).cwiseAbs().maxCoeff() <= 1e-12 * in.B.cwiseAbs().maxCoeff());
    CHECK((q.udot - in.udot).cwiseAbs().maxCoeff() <= 1e-10 * in.udot.cwiseAbs().maxCoeff());
    CHECK(q.kinetic + q.potential == Approx(in.kinetic + in.potential).epsilon(1e-12).margin(1e-12));
  }
}
