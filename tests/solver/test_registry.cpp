// The registry and the run settings: every row is reachable by its name, the
// properties other parts branch on are the ones each method and integrator
// has, and the settings checks refuse what cannot be run (naming the field).
#include <catch2/catch.hpp>

#include "solver/dynamics.hpp"
#include "solver/run_spec.hpp"
#include "solver/text.hpp"
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
  for (const IntegratorInfo& i : integratorTable()) CHECK_FALSE(i.engines.empty());  // every row runs somewhere
  CHECK(info(Integrator::RK4).runs(Engine::InHouse));
  CHECK_THROWS_WITH(parseMethod("newton"),
                    "unknown method 'newton' (classical, articulated, eigen, eigen-jacobi, eigen-jacobi-orth, eigen-block, eigen-block-jacobi)");
  CHECK_THROWS_WITH(parseIntegrator("verlet"), Catch::Contains("unknown integrator 'verlet'") && Catch::Contains("rk8pd"));
}

TEST_CASE("the registry's properties are what each method does", "[registry][dynamics]") {
  // The state layout, correctsAfterStep and the diagnostics follow the row, and
  // the engines' defaults run on their engine.
  const Model m = test::loadData("pendulum5.json");
  const int N = m.nu;
  const Eigen::MatrixXd A = equationsAtStart(m).A;
  const Eigen::VectorXd eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues();
  for (const MethodInfo& row : methodTable()) {
    if (row.engine != Engine::InHouse) {
      CHECK_THROWS_AS(Dynamics(m, row.id), std::invalid_argument);
      continue;
    }
    Dynamics dyn(m, row.id);
    INFO(row.name);
    CHECK(dyn.size() == m.nq + m.nu + extraStateSize(row.extra, N));
    // eigen-block re-clusters after every step whatever its correction.
    CHECK(dyn.correctsAfterStep() == (row.extra == ExtraState::CD || row.correction != Correction::None));
    CHECK(dyn.eigenfactor() == row.eigenfactor);
    if (row.extra == ExtraState::None) continue;
    // The layout the row names: C (orthogonal) first, then lambda or D holding A's eigenvalues.
    const Eigen::VectorXd y = dyn.initialState(m.q0(), m.u0());
    const Eigen::Map<const RowMatrix> C(y.data() + dyn.offsetExtra(), N, N);
    CHECK((C * C.transpose() - Eigen::MatrixXd::Identity(N, N)).norm() < 1e-13);  // eigensolver round-off
    Eigen::VectorXd held = row.extra == ExtraState::CLambda
                               ? Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(y.data() + dyn.offsetExtra() + N * N, N))
                               : Eigen::VectorXd(Eigen::Map<const Eigen::MatrixXd>(y.data() + dyn.offsetExtra() + N * N, N, N).diagonal());
    // Both layouts hold them ascending (the eigensolver's order, eigen-block's clusters sorted).
    CHECK((held - eigenvalues).cwiseAbs().maxCoeff() < 1e-13 * eigenvalues.maxCoeff());
    CHECK((C.transpose() * held.asDiagonal() * C - A).norm() < 1e-13 * A.norm());
  }
  CHECK(info(defaultIntegrator(Engine::InHouse)).runs(Engine::InHouse));
  CHECK_FALSE(info(adaptiveIntegrator(Engine::InHouse)).fixed_step);
  for (const IntegratorInfo& i : integratorTable())  // an in-house row names its step function, its GSL stepper or its own solver
    if (i.runs(Engine::InHouse)) {
      INFO(i.name);
      CHECK(i.stepped());
      CHECK(int(i.stepsItself()) + int(i.multistep) + int(i.step != nullptr) + int(i.gsl != nullptr) == 1);  // exactly one way
    }
  CHECK_NOTHROW(requireCompatible(Method::Classical, Integrator::BSIMP));
}

TEST_CASE("another engine is added at run time: its method, its schemes, a shared tableau and its tolerance bound", "[registry]") {
  // What reference/table.cpp does for every engine's row, on a made-up engine.
  const size_t methods = methodTable().size(), integrators = integratorTable().size();
  EngineInfo row;
  row.name = "toy";
  row.summary = "a made-up engine";
  row.schemes = {{"rk4", true, "the in-house tableau", "o"}, {"toy-sdirk", false, "adaptive", "*"}};
  row.fixed_scheme = "rk4";
  row.adaptive_scheme = "toy-sdirk";
  row.max_tol = 1.0;
  const Engine toy = addEngine(row);
  CHECK(static_cast<int>(toy) == 1);  // ids follow the built-in ones
  CHECK(parseEngine("toy") == toy);
  const Method m = info(toy).method;
  CHECK(methodTable().size() == methods + 1);
  CHECK(info(m).engine == toy);
  CHECK(info(m).make == nullptr);  // its own runner, not the in-house integrators
  CHECK(methodNames().back() == "toy");
  // One name, one scheme: rk4 is a row already, which now lists the engine too; toy-sdirk is new.
  CHECK(integratorTable().size() == integrators + 1);
  CHECK(info(Integrator::RK4).runs(toy));
  CHECK(integratorNames(toy) == std::vector<std::string>{"rk4", "toy-sdirk"});
  CHECK(defaultIntegrator(toy) == Integrator::RK4);
  // Its code tells its schemes apart by id, their place in its row (shared tableau or not), never by name.
  CHECK(schemeIndex(toy, Integrator::RK4) == 0);
  CHECK(schemeIndex(toy, adaptiveIntegrator(toy)) == 1);
  CHECK_THROWS_AS(schemeIndex(toy, Integrator::RK8PD), std::logic_error);
  CHECK_FALSE(info(adaptiveIntegrator(toy)).fixed_step);
  CHECK(hasAdaptiveScheme(toy));
  CHECK(otherEngines() == std::vector<Engine>{toy});
  CHECK_NOTHROW(requireCompatible(m, Integrator::RK4));
  CHECK_THROWS_WITH(requireCompatible(m, Integrator::RK8PD), Catch::Contains("rk8pd") && Catch::Contains("toy"));
  CHECK_THROWS_AS(requireCompatible(Method::Classical, adaptiveIntegrator(toy)), std::invalid_argument);
  // Its tolerance bound is checked before any run, naming tol (Simbody asserts on an accuracy >= 1).
  RunSpec s = test::runSpec(m, adaptiveIntegrator(toy), 1.0, 1.0);
  try {
    checkRunSpec(s);
    FAIL("tolerance 1 accepted");
  } catch (const SettingError& e) {
    CHECK(e.field == "tol");
    CHECK(e.detail == "toy's tolerance must be < 1, got 1");
  }
  s.tol = 0.5;
  CHECK_NOTHROW(checkRunSpec(s));
  CHECK(methodOwner(m) == "toy");  // the engine study files its route under its engine
  CHECK_THROWS_AS(addEngine(row), std::logic_error);  // one name, one row
  row.name = "classical";
  CHECK_THROWS_AS(addEngine(row), std::logic_error);  // a method's name
}

TEST_CASE("a method from outside is added at run time and refused under a taken name", "[registry]") {
  MethodInfo row;  // the in-house integrators run it through its factory
  row.name = "mine";
  row.make = info(Method::Classical).make;
  row.summary = "a user's method";
  const Method m = addMethod(row);
  CHECK(methodOwner(m) == "mine");  // its own route in the engine study, not eigenmass's
  CHECK(methodOwner(Method::EigenBlockJacobi) == "eigenmass");
  CHECK(parseMethod("mine") == m);
  CHECK(info(m).engine == Engine::InHouse);
  CHECK(static_cast<int>(m) > static_cast<int>(Method::EigenBlockJacobi));  // after the built-ins (and any row added before)
  row.name = "eigen";
  CHECK_THROWS_WITH(addMethod(row), "the method name 'eigen' is taken");
}

TEST_CASE("a method's own options are columns of its row: set, defaulted, or refused by name", "[registry]") {
  const MethodInfo& block = info(Method::EigenBlock);
  MethodOptions o;
  CHECK(block.param("block_gap", o) == 3e-2);  // the row's fallback
  CHECK(block.param("refine", o) == 0);        // the paper's u'
  o.params["block_gap"] = 0.1;
  CHECK(block.param("block_gap", o) == 0.1);
  CHECK_FALSE(info(Method::Eigen).takes("block_gap"));
  CHECK_THROWS_AS(info(Method::Classical).param("refine", o), std::logic_error);
  std::vector<std::string> names;
  for (const MethodParam& p : methodParams()) names.emplace_back(p.name);
  CHECK(names == std::vector<std::string>{"refine", "refine_tol", "block_gap"});  // once each, in table order
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

TEST_CASE("a method from outside is retired after its call: its name freed and unlisted, its id still read", "[registry]") {
  MethodInfo row;
  row.name = "for-one-call";
  row.summary = "a Python function's row";
  const Method m = addMethod(row);
  Method found;
  REQUIRE(findMethod("for-one-call", found));
  retireMethod(m);
  CHECK_FALSE(findMethod("for-one-call", found));
  const std::vector<std::string> names = methodNames();
  CHECK(std::count(names.begin(), names.end(), "for-one-call") == 0);
  CHECK(std::string(methodName(m)) == "for-one-call");  // a report made in the call still names it
  row.name = "for-one-call";
  CHECK(addMethod(row) != m);  // the name is free again: a new row
  CHECK_THROWS_AS(retireMethod(Method::Classical), std::logic_error);  // built-in rows stay
}

TEST_CASE("a number beyond its bound is printed with the digits that tell them apart", "[text]") {
  // Issue 53 item 20: "1 beyond 1 rad" for 1.0000001, "1e+06 samples, more than the budget of 1e+06".
  CHECK(gnumApart(1.0000001, 1) == std::make_pair(std::string("1.0000001"), std::string("1")));
  CHECK(gnumApart(1000001, 1e6, 3) == std::make_pair(std::string("1000001"), std::string("1000000")));
  CHECK(gnumApart(2e6, 1e6, 3) == std::make_pair(std::string("2e+06"), std::string("1e+06")));
  CHECK(gnumApart(1, 1) == std::make_pair(std::string("1"), std::string("1")));
  CHECK(gnumApart(1 + 1e-15, 1).first != gnumApart(1 + 1e-15, 1).second);
}
