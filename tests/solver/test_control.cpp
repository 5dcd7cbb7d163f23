// Joint-space control (docs/theory.md §18, solver/control.cpp) against closed
// forms: a PD-controlled joint without gravity is a damped oscillator
// (continuous), and under a zero-order hold its samples follow the exact
// discretization of a double integrator; a clamped loop accelerates at
// effort / I; a torque table ramps a joint as t^3 / (6 I); a sine target's
// response is the oscillator's forced one. E + W_diss holds, W_diss counting
// the controller's work negative (eq. (C3)).
#include <cmath>
#include <complex>

#include <catch2/catch.hpp>

#include "io/json_input.hpp"
#include "io/scene.hpp"
#include "solver/integrate.hpp"
#include "support.hpp"

using namespace em;

namespace {

// One joint about z through the body's CM: I = 0.5 kg m^2 about the axis, no
// gravity; `control` is the joint's "control" object, `extra` more joint keys.
std::string armScene(const std::string& control, const std::string& gravity = "[0, 0, 0]") {
  return R"({"format": "eigenmass-scene/1", "name": "arm", "gravity": )" + gravity +
         R"(, "bodies": [{"name": "arm", "parent": "ground", "mass": 1, "inertia": [1, 1, 0.5],
   "joint": {"type": "revolute", "axis": [0, 0, 1], "in_parent": [0, 0, 0], "in_body": [0, 0, 0], "control": )" + control +
         "}}], \"simulate\": {\"t_end\": 5, \"output_dt\": 0.01}}";
}
Model arm(const std::string& control) { return loadSceneText(armScene(control), "arm.json").model; }

constexpr double kI = 0.5, kKp = 8, kKd = 0.4;
const std::string kPd = R"({"type": "pd", "kp": 8, "kd": 0.4, "target": {"type": "constant", "q": 1}})";

// I th'' + kd th' + kp th = kp from rest at 0: the underdamped step response.
double stepResponse(double t) {
  const double wn = std::sqrt(kKp / kI), z = kKd / (2 * std::sqrt(kKp * kI)), wd = wn * std::sqrt(1 - z * z);
  return 1 - std::exp(-z * wn * t) * (std::cos(wd * t) + z / std::sqrt(1 - z * z) * std::sin(wd * t));
}

double balanceSpread(const Trajectory& tr) {
  double lo = 1e300, hi = -1e300;
  for (size_t k = 0; k < tr.t.size(); ++k) lo = std::min(lo, tr.energy[k] + tr.dissipated[k]), hi = std::max(hi, tr.energy[k] + tr.dissipated[k]);
  return hi - lo;
}

}  // namespace

TEST_CASE("a continuous PD loop on a joint without gravity is the damped oscillator's closed form", "[control]") {
  const Model m = arm(kPd);
  for (const Method method : {Method::Classical, Method::Articulated, Method::Eigen}) {
    INFO(methodName(method));
    const Trajectory tr = simulate(m, checked(test::runSpec(method, Integrator::RK8PD, 5.0, 1e-12)));
    REQUIRE_FALSE(tr.failed());
    double worst = 0;
    for (size_t k = 0; k < tr.t.size(); ++k) worst = std::max(worst, std::abs(tr.q[k][0] - stepResponse(tr.t[k])));
    CHECK(worst < 1e-10);  // rk8pd at 1e-12 over 5 s: 9e-16 measured (classical)
    // The loop's work leaves E + W_diss constant; its power is -tau u in W_diss'.
    CHECK(balanceSpread(tr) < 1e-10);
    CHECK(tr.dissipated.back() == Approx(-tr.energy.back()).epsilon(1e-9));  // started at rest with E = 0
  }
  // rk4 is fourth order on it: dt 1e-2 -> 7.9e-8, 1e-3 -> 7.9e-12 (measured).
  double err[2];
  for (int i = 0; i < 2; ++i) {
    const Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 5.0, i ? 1e-3 : 1e-2)));
    err[i] = 0;
    for (size_t k = 0; k < tr.t.size(); ++k) err[i] = std::max(err[i], std::abs(tr.q[k][0] - stepResponse(tr.t[k])));
  }
  CHECK(err[0] / err[1] == Approx(1e4).epsilon(0.1));
}

TEST_CASE("a sampled PD loop follows the zero-order hold's exact discretization", "[control]") {
  const Model m = arm(R"({"type": "pd", "kp": 8, "kd": 0.4, "period": 0.01, "target": {"type": "constant", "q": 1}})");
  REQUIRE(m.control_period == 0.01);
  for (const auto& [integrator, setting] : {std::pair{Integrator::RK8PD, 1e-12}, std::pair{Integrator::RK4, 1e-3}, std::pair{Integrator::RKF45, 1e-11}}) {
    INFO(integratorName(integrator));
    const Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, integrator, 5.0, setting)));
    REQUIRE_FALSE(tr.failed());
    // Between samples tau is constant, so (theta, omega) advance by
    // Phi = [1 T; 0 1], Gamma = [T^2 / 2I; T / I] exactly; outputs fall on samples (both 0.01 s).
    double th = 0, w = 0, worst = 0;
    for (size_t k = 1; k < tr.t.size(); ++k) {
      const double T = 0.01, tau = kKp * (1 - th) - kKd * w;
      th += T * w + T * T / (2 * kI) * tau;
      w += T / kI * tau;
      worst = std::max(worst, std::abs(tr.q[k][0] - th) + std::abs(tr.u[k][0] - w));
    }
    // The motion between samples is a quadratic: rk4 and rk8pd are exact on it
    // (4e-15 measured); rkf45 at 1e-11 is the tolerance's.
    CHECK(worst < (integrator == Integrator::RKF45 ? 1e-9 : 1e-12));
    CHECK(balanceSpread(tr) < 1e-10);
  }
  // The held loop is not the continuous one: T = 0.01 moves the response by O(T).
  const Trajectory held = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 5.0, 1e-3)));
  double apart = 0;
  for (size_t k = 0; k < held.t.size(); ++k) apart = std::max(apart, std::abs(held.q[k][0] - stepResponse(held.t[k])));
  CHECK(apart > 1e-3);
}

TEST_CASE("a clamped loop accelerates at effort / I; a torque table ramps a joint as t^3 / 6I", "[control]") {
  SECTION("effort") {
    // kp 1e4 toward 1 rad: the loop asks for far more than 0.1 N m until theta nears 1.
    const Model m = arm(R"({"type": "pd", "kp": 1e4, "kd": 0, "effort": 0.1, "target": {"type": "constant", "q": 1}})");
    const Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 3.0, 1e-12)));
    REQUIRE_FALSE(tr.failed());
    for (size_t k = 0; k < tr.t.size(); ++k)
      if (tr.t[k] <= 3.0) CHECK(tr.q[k][0] == Approx(0.5 * 0.1 / kI * tr.t[k] * tr.t[k]).margin(1e-12));  // theta(3) = 0.9 < 1
  }
  SECTION("torque table") {
    const Model m = arm(R"({"type": "table", "t": [0, 1, 2], "tau": [0, 1, 1]})");
    const Trajectory tr = simulate(m, checked(test::runSpec(Method::Articulated, Integrator::RK4, 2.0, 1e-3)));
    REQUIRE_FALSE(tr.failed());
    for (size_t k = 0; k < tr.t.size(); ++k) {
      const double t = tr.t[k];
      // tau = t on [0, 1], then 1: theta = t^3 / 6I, then 1/6I + (t - 1)/2I + (t - 1)^2 / 2I.
      const double exact = t <= 1 ? t * t * t / (6 * kI) : (1.0 / 6 + 0.5 * (t - 1) + 0.5 * (t - 1) * (t - 1)) / kI;
      CHECK(tr.q[k][0] == Approx(exact).margin(1e-12));  // piecewise cubic, steps on its kink (dt 1e-3 divides 1 s): rk4 exact
    }
    CHECK(tr.dissipated.back() == Approx(-tr.energy.back()).epsilon(1e-12));  // the table's work is the kinetic energy
  }
}

TEST_CASE("a PD loop tracking a sine is the forced oscillator's closed form", "[control]") {
  const Model m = arm(R"({"type": "pd", "kp": 8, "kd": 0.4, "target": {"type": "sine", "offset": 0, "amplitude": 0.3, "frequency_hz": 0.7}})");
  const Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 5.0, 1e-12)));
  REQUIRE_FALSE(tr.failed());
  // I th'' + kd th' + kp th = kp a sin(w t) + kd a w cos(w t) = Im[(kp + i kd w) a e^{iwt}]:
  // theta_p = Im[H a e^{iwt}], H = (kp + i kd w) / (kp - I w^2 + i kd w), plus the free response from rest.
  const double a = 0.3, w = 2 * M_PI * 0.7;
  const std::complex<double> H = std::complex<double>(kKp, kKd * w) / std::complex<double>(kKp - kI * w * w, kKd * w);
  const double wn = std::sqrt(kKp / kI), z = kKd / (2 * std::sqrt(kKp * kI)), wd = wn * std::sqrt(1 - z * z);
  const double C1 = -std::imag(H * a), C2 = (z * wn * C1 - std::real(H * a) * w) / wd;  // theta(0) = theta'(0) = 0
  double worst = 0;
  for (size_t k = 0; k < tr.t.size(); ++k) {
    const double t = tr.t[k];
    const double exact = std::imag(H * a * std::exp(std::complex<double>(0, w * t))) + std::exp(-z * wn * t) * (C1 * std::cos(wd * t) + C2 * std::sin(wd * t));
    worst = std::max(worst, std::abs(tr.q[k][0] - exact));
  }
  CHECK(worst < 1e-10);
}

TEST_CASE("a controlled double pendulum under gravity: classical, articulated and eigen agree, and E + W_diss holds", "[control]") {
  const std::string scene = R"({"format": "eigenmass-scene/1", "name": "arm2", "gravity": [0, -9.81, 0], "bodies": [
    {"name": "a", "parent": "ground", "mass": 1, "inertia": [0.001, 0.0833, 0.0833],
     "joint": {"type": "revolute", "axis": [0, 0, 1], "in_parent": [0, 0, 0], "in_body": [-0.5, 0, 0], "q0": [0.3],
               "control": {"type": "pd", "kp": [40], "kd": [2], "effort": 15, "target": {"type": "table", "t": [0, 1, 2], "q": [0, 1, -0.5]}}}},
    {"name": "b", "parent": "a", "mass": 1, "inertia": [0.001, 0.0833, 0.0833],
     "joint": {"type": "revolute", "axis": [0, 0, 1], "in_parent": [0.5, 0, 0], "in_body": [-0.5, 0, 0],
               "control": {"type": "pd", "kp": 20, "kd": 1, "target": {"type": "sine", "offset": [0.2], "amplitude": [0.5], "frequency_hz": [1]}}}}]})";
  const Model m = loadSceneText(scene, "arm2.json").model;
  const Trajectory ref = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 3.0, 1e-12)));
  REQUIRE_FALSE(ref.failed());
  CHECK(balanceSpread(ref) < 1e-9);
  for (const Method method : {Method::Articulated, Method::Eigen}) {
    INFO(methodName(method));
    const Trajectory tr = simulate(m, checked(test::runSpec(method, Integrator::RK8PD, 3.0, 1e-12)));
    REQUIRE_FALSE(tr.failed());
    CHECK(test::stateDiff(tr, ref, 3.0) < 1e-8);
  }
}

TEST_CASE("a controller the integrator cannot run is refused in one line", "[control]") {
  const Model sampled = arm(R"({"type": "pd", "kp": 8, "kd": 0.4, "period": 0.005, "target": {"type": "constant", "q": 1}})");
  RunSpec spec = test::runSpec(Method::Classical, Integrator::RK4, 1.0, 2e-3);
  CHECK_THROWS_WITH(simulate(sampled, checked(spec)), Catch::Contains("option --dt") && Catch::Contains("does not divide the control period"));
  spec = test::runSpec(Method::Classical, Integrator::CVODE, 1.0, 1e-8);
  CHECK_THROWS_WITH(simulate(sampled, checked(spec)), Catch::Contains("stops at each sample"));
  spec = test::runSpec(Method::Classical, Integrator::IDA, 1.0, 1e-8);
  CHECK_THROWS_WITH(simulate(arm(kPd), checked(spec)), Catch::Contains("joint control is not built into its own formation"));
}

TEST_CASE("malformed controls are refused naming the key", "[control]") {
  const auto refused = [](const std::string& control, const std::string& where, const std::string& what) {
    INFO(control);
    CHECK_THROWS_WITH(loadSceneText(armScene(control), "arm.json"), Catch::Contains(where) && Catch::Contains(what));
  };
  refused(R"({"type": "pd", "kp": -1, "kd": 0, "target": {"type": "constant", "q": 0}})", "control.kp", ">= 0");
  refused(R"({"type": "pd", "kp": 1, "kd": 0, "target": {"type": "table", "t": [0, 2, 1], "q": [0, 1, 2]}})", "target.t[2]", "not after");
  refused(R"({"type": "table", "t": [0, 1], "tau": [0]})", "control.tau", "one row per time");
  refused(R"({"type": "pd", "kp": 1, "kd": 0, "effort": 0, "target": {"type": "constant", "q": 0}})", "control.effort", "> 0");
  refused(R"({"type": "pd", "kp": 1, "kd": 0, "period": 0, "target": {"type": "constant", "q": 0}})", "control.period", "outside");
  refused(R"({"type": "pd", "kp": 1, "kd": 0, "target": {"type": "sine", "offset": 0, "amplitude": 1, "frequency_hz": -2}})", "frequency_hz", "outside");
  refused(R"({"type": "pid", "kp": 1})", "control.type", "unknown control type");
  refused(R"({"type": "pd", "kp": 1, "kd": 0, "target": {"type": "constant", "q": 0}, "ki": 1})", "control", "ki");
}
