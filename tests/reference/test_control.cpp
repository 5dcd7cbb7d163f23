// Every engine under a joint controller (docs/theory.md §18,
// reference/fixed_step.cpp, reference/simbody.cpp): sampled every 10 ms from
// the engine's own state and held, a PD loop on one joint without gravity
// must follow the zero-order hold's exact discretization at the samples.
// MuJoCo's rk4 is exact on the motion between samples (a quadratic), Simbody
// to its tolerance; the semi-implicit Euler engines (ODE, Bullet, DART)
// converge to it at first order in dt. Measured at dt 1e-4: MuJoCo 3.0e-14
// rad; ODE, Bullet, DART 4.1e-4; Simbody rkmerson at 1e-10: 1.4e-15.
#include <catch2/catch.hpp>

#include <cmath>

#include "compare/engines.hpp"
#include "engines.hpp"
#include "support.hpp"

using namespace em;

namespace {

Model sampledArm() { return loadScene(test::sourcePath("tests/scenes/control/pd_arm_sampled.json")).model; }

// The largest gap of (theta, omega) at the samples from the exact hold:
// Phi = [1 T; 0 1], Gamma = [T^2 / 2I; T / I], tau = kp (1 - theta) - kd omega.
double holdError(const Trajectory& tr) {
  const double I = 0.5, kp = 8, kd = 0.4, T = 0.01;
  double th = 0, w = 0, worst = 0;
  for (size_t k = 1; k < tr.t.size(); ++k) {
    const double tau = kp * (1 - th) - kd * w;
    th += T * w + T * T / (2 * I) * tau;
    w += T / I * tau;
    worst = std::max(worst, std::abs(tr.q[k][0] - th));
  }
  return worst;
}

double balanceSpread(const Trajectory& tr) {
  double lo = 1e300, hi = -1e300;
  for (size_t k = 0; k < tr.t.size(); ++k) lo = std::min(lo, tr.energy[k] + tr.dissipated[k]), hi = std::max(hi, tr.energy[k] + tr.dissipated[k]);
  return hi - lo;
}

Trajectory run(const Model& m, const char* method, const char* scheme, double setting) {
  const Trajectory tr = runTrajectory(m, checked(test::runSpec(test::method(method), test::scheme(scheme), 5.0, setting)));
  REQUIRE_FALSE(tr.failed());
  return tr;
}

}  // namespace

TEST_CASE("every engine samples a joint controller from its own state and holds it: the zero-order hold's samples", "[control][engines]") {
  const Model m = sampledArm();
  SECTION("MuJoCo's rk4 and Simbody are exact on it, and keep E + W_diss") {
    const Trajectory mj = run(m, "mujoco", "rk4", 1e-3);
    CHECK(holdError(mj) < 1e-11);           // 3e-14 measured: rk4 is exact on a quadratic
    CHECK(balanceSpread(mj) < 1e-11);       // W_diss counts tau . dq, exact under the hold
    for (const char* scheme : {"rkmerson", "cpodes"}) {
      INFO(scheme);
      const Trajectory sb = run(m, "simbody", scheme, 1e-10);
      CHECK(holdError(sb) < 1e-7);          // 1.4e-15 rkmerson, 7.9e-9 cpodes (measured)
      CHECK(balanceSpread(sb) < 1e-6);
    }
  }
  SECTION("the semi-implicit Euler engines converge to it at first order") {
    for (const char* engine : {"ode", "bullet", "dart"}) {
      INFO(engine);
      const char* scheme = std::string(engine) == "ode" ? "ode-step" : std::string(engine) == "bullet" ? "bullet-euler" : "dart-euler";
      const double coarse = holdError(run(m, engine, scheme, 1e-3)), fine = holdError(run(m, engine, scheme, 1e-4));
      CHECK(fine < 1e-3);                    // 4.1e-4 measured at dt 1e-4
      CHECK(coarse / fine == Approx(10).epsilon(0.3));  // first order
    }
  }
}

TEST_CASE("a controller an engine cannot run as asked is refused in one line", "[control][engines]") {
  const Model m = sampledArm();
  // dt 3e-3 does not divide the 10 ms period (output_dt 0.03 keeps the grid whole).
  RunSpec spec = test::runSpec(test::method("mujoco"), test::scheme("rk4"), 0.3, 3e-3, 0.03);
  CHECK_THROWS_WITH(runTrajectory(m, checked(spec)), Catch::Contains("option --dt") && Catch::Contains("control period"));
  // An engine's u' under our integrators knows no controller.
  spec = test::runSpec(test::method("mujoco-udot"), Integrator::RK4, 1.0, 1e-3);
  CHECK_THROWS_WITH(runTrajectory(m, checked(spec)), Catch::Contains("knows no joint controller"));
}
