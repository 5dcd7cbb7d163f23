// Every engine's own stops (docs/reference-engines.md, "Joint limits";
// reference/fixed_step.cpp watches them after every step) against the
// in-house exact events (docs/theory.md §17). ODE maps e as dParamBounce: its
// impacts follow the impact law to first order in dt. MuJoCo (soft, its
// default solreflimit), DART and Bullet have no restitution: their stops are
// inelastic, which the rebound shows. Measured (tools/limit_engines.py): ODE
// at dt 1e-4, first impact 5e-5 s early (half a step: the crossing lies
// within the step), rebound within 2.3e-4 rad/s or m/s on four scenes;
// MuJoCo lets a stop be passed by 0.035 rad whatever dt, DART by 5e-12.
#include <catch2/catch.hpp>

#include <cmath>

#include "compare/engines.hpp"
#include "compare/metrics.hpp"
#include "engines.hpp"
#include "io/json_input.hpp"
#include "support.hpp"

using namespace em;

namespace {

Model stopScene(const std::string& name) { return loadScene(test::sourcePath("tests/scenes/limits/" + name)).model; }

Trajectory exact(const Model& m, double t_end) {
  const Trajectory tr = runTrajectory(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, t_end, 1e-10, 1e-3)));
  REQUIRE_FALSE(tr.failed());
  return tr;
}

ImpactCheck engineRun(const Model& m, const Trajectory& ref, const char* method, const char* scheme, double dt) {
  const Trajectory tr = runTrajectory(m, checked(test::runSpec(test::method(method), test::scheme(scheme), ref.run.t_end, dt, 1e-3)));
  REQUIRE_FALSE(tr.failed());
  return checkImpacts(tr, ref);
}

}  // namespace

TEST_CASE("ODE's stops with dParamBounce = e follow the impact law to first order in dt", "[limits][engines]") {
  for (const char* name : {"pendulum_stop.json", "double_hinge_stop.json", "cart_slide_stop.json", "slide_floor.json"}) {
    INFO(name);
    const Model m = stopScene(name);
    const Trajectory ref = exact(m, 2.0);
    const ImpactCheck coarse = engineRun(m, ref, "ode", "ode-step", 1e-3), fine = engineRun(m, ref, "ode", "ode-step", 1e-4);
    CHECK(std::abs(fine.first_time_error) < 1e-4);      // 5e-5 measured: the crossing within the step
    CHECK(std::abs(fine.first_rebound_error) < 1e-3);   // 2.3e-4 measured at most
    CHECK(std::abs(coarse.first_time_error / fine.first_time_error) == Approx(10).epsilon(0.3));  // first order
    CHECK(fine.overshoot_max < 1e-3);                    // its stop ERP pulls it back within a step or two
    // Every impact of the reference is met, but the block's Zeno tail (24 impacts, the last ones ~1e-6 m/s) is below ODE's step.
    if (std::string(name) != "slide_floor.json") CHECK(fine.count == ref.impact_count);
  }
}

TEST_CASE("MuJoCo's, DART's and Bullet's stops are inelastic, each passing its stop as its mechanism does", "[limits][engines]") {
  const Model m = stopScene("pendulum_stop.json");
  const Trajectory ref = exact(m, 1.0);
  const double v = std::abs(ref.impacts.at(0).u_before);  // 4.856 rad/s onto the stop, e = 1 rebounds at v
  struct Route {
    const char* method;
    const char* scheme;
    double time_tol, overshoot_lo, overshoot_hi;
  };
  // MuJoCo rk4: soft (solreflimit 0.02 1), the crossing itself exact to 1.6e-5 s, 0.035 rad beyond;
  // DART: held at the stop to round-off; Bullet: its constraint solver, 1.4e-5 rad at dt 1e-3 (measured).
  for (const Route& r : {Route{"mujoco", "rk4", 1e-4, 0.02, 0.05}, Route{"dart", "dart-euler", 2e-3, 0, 1e-9},
                         Route{"bullet", "bullet-euler", 2e-3, 0, 1e-3}}) {
    INFO(r.method);
    const ImpactCheck c = engineRun(m, ref, r.method, r.scheme, 1e-3);
    REQUIRE(c.compared >= 1);
    CHECK(std::abs(c.first_time_error) < r.time_tol);
    CHECK(std::abs(ref.impacts[0].u_after + c.first_rebound_error) < 0.2 * v);  // its rebound: a fifth of the law's at most
    CHECK(c.overshoot_max >= r.overshoot_lo);
    CHECK(c.overshoot_max <= r.overshoot_hi);
  }
}

TEST_CASE("an engine's stop options are its own stops' softness: MuJoCo's solreflimit damping sets its rebound", "[limits][engines]") {
  const Model m = stopScene("pendulum_stop.json");
  const Trajectory ref = exact(m, 1.0);
  double last = HUGE_VAL;
  // Measured at dt 1e-4: rebound 4.19, 2.67, 0.688 rad/s short of the law's 4.86 at damping ratios 1, 0.3, 0.05.
  for (double ratio : {1.0, 0.3, 0.05}) {
    RunSpec spec = test::runSpec(test::method("mujoco"), test::scheme("rk4"), 1.0, 1e-4, 1e-3);
    spec.options.params["mujoco_limit_solref_damping"] = ratio;
    const ImpactCheck c = checkImpacts(runTrajectory(m, checked(spec)), ref);
    INFO("damping ratio " << ratio << ": rebound off by " << c.first_rebound_error);
    CHECK(std::abs(c.first_rebound_error) < 0.8 * last);
    last = std::abs(c.first_rebound_error);
  }
  CHECK(last < 1.0);
  // ODE's stop CFM softens its stop: the block on the floor sinks further (measured at dt 1e-3: 7.8e-3 m at
  // CFM 1e-3 against 4.3e-3 m at its default 1e-10). Its stop ERP changed nothing measurable on these scenes.
  const Model block = stopScene("slide_floor.json");
  const Trajectory floor = exact(block, 2.0);
  RunSpec soft = test::runSpec(test::method("ode"), test::scheme("ode-step"), 2.0, 1e-3, 1e-3);
  soft.options.params["ode_stop_cfm"] = 1e-3;
  const ImpactCheck a = checkImpacts(runTrajectory(block, checked(soft)), floor), b = engineRun(block, floor, "ode", "ode-step", 1e-3);
  CHECK(a.overshoot_max > 1.5 * b.overshoot_max);
}

TEST_CASE("an engine that cannot stop a joint as the scene asks is refused in one line, naming itself", "[limits][engines]") {
  const Model m = stopScene("pendulum_stop.json");
  CHECK_THROWS_WITH(runTrajectory(m, checked(test::runSpec(test::method("simbody"), test::scheme("rkmerson"), 1.0, 1e-8))),
                    Catch::Contains("simbody") && Catch::Contains("no mapping of joint limits"));
  // ODE's hinge angle lives in [-pi, pi]: a stop beyond it is none of ODE's.
  std::string text = readFile(test::sourcePath("tests/scenes/limits/pendulum_stop.json"), "scene");
  const size_t at = text.find("\"upper\": [3.0]");
  REQUIRE(at != std::string::npos);
  text.replace(at, 14, "\"upper\": [4.0]");
  const Model wide = loadSceneText(text, "wide.json").model;
  CHECK_THROWS_WITH(runTrajectory(wide, checked(test::runSpec(test::method("ode"), test::scheme("ode-step"), 1.0, 1e-3))),
                    Catch::Contains("ode") && Catch::Contains("[-pi, pi]"));
}
