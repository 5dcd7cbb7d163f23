// Joint limits as exact events (docs/theory.md §17, solver/limits.cpp),
// against closed forms: a pendulum against a stop with e = 1 (its period by
// quadrature), a block bouncing on a floor (the impact times' geometric
// series and Zeno's point), and the energy balance of a double pendulum whose
// shoulder hits its stops (impulses through A).
#include <cmath>

#include <catch2/catch.hpp>
#include <gsl/gsl_integration.h>

#include "io/scene.hpp"
#include "solver/integrate.hpp"
#include "support.hpp"

using namespace em;

namespace {

Model limitScene(const std::string& name) { return loadScene(test::sourcePath("tests/scenes/limits/" + name)).model; }

// The rod of pendulum_stop.json: I about the pivot = m L^2 / 3, CM at l = L / 2.
struct Rod {
  double I = 1.0 / 3, g = 9.81, l = 0.5, theta0 = -0.2;
  double rate(double th) const { return std::sqrt(2 * g * l * (std::sin(theta0) - std::sin(th)) / I); }
};

// Time from release at theta0 to the stop at -pi/2 (GSL's QAGS: the
// integrand's 1/sqrt at theta0 is integrable).
double fallTime(const Rod& rod) {
  gsl_integration_workspace* w = gsl_integration_workspace_alloc(200);
  gsl_function f{[](double th, void* p) { return 1.0 / static_cast<const Rod*>(p)->rate(th); }, const_cast<Rod*>(&rod)};
  double t = 0, err = 0;
  gsl_integration_qags(&f, -M_PI / 2, rod.theta0, 1e-15, 1e-13, 200, w, &t, &err);
  gsl_integration_workspace_free(w);
  return t;
}

}  // namespace

TEST_CASE("a pendulum against a stop with e = 1 is periodic: its impacts at odd multiples of the fall time", "[limits]") {
  const Model m = limitScene("pendulum_stop.json");
  const double t_fall = fallTime(Rod{});  // 0.46349707529... s
  for (const auto& [integrator, setting] : {std::pair{Integrator::RK8PD, 1e-12}, std::pair{Integrator::RK4, 1e-3}}) {
    INFO(integratorName(integrator));
    const Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, integrator, 20.0, setting)));
    REQUIRE_FALSE(tr.failed());
    REQUIRE(tr.impact_count == 22);  // 20 s / (2 t_fall) = 21.6
    double worst = 0;
    for (size_t k = 0; k < tr.impacts.size(); ++k) worst = std::max(worst, std::abs(tr.impacts[k].t - (2.0 * k + 1) * t_fall));
    // rk8pd at 1e-12: 1.5e-11 s (measured); rk4 at dt 1e-3 carries its own O(dt^4) error in the motion (measured 2.6e-10 s).
    CHECK(worst < (integrator == Integrator::RK8PD ? 1e-9 : 1e-8));
    const double v = Rod{}.rate(-M_PI / 2);  // the speed at the stop, by energy
    for (const Impact& i : tr.impacts) {
      CHECK(i.u_before == Approx(-v).epsilon(1e-8));
      CHECK(i.u_after == Approx(v).epsilon(1e-8));  // e = 1: reversed
      CHECK(std::abs(i.energy_lost) < 1e-10);
    }
    for (size_t k = 0; k < tr.t.size(); ++k) CHECK(std::abs(tr.energy[k] - tr.energy[0]) < 1e-8);
    // never beyond the stop at a sample
    for (const Eigen::VectorXd& q : tr.q) CHECK(q[0] >= -M_PI / 2 - 1e-12);
  }
}

TEST_CASE("a block on a floor with e = 0.5: impact times form a geometric series, it rests after Zeno's point", "[limits]") {
  const Model m = limitScene("slide_floor.json");
  const double g = 9.81, e = 0.5, t1 = std::sqrt(2 * 1.0 / g), v1 = g * t1;
  const double zeno = t1 + 2 * e * v1 / g / (1 - e);  // t1 + sum of 2 e^k v1 / g
  // rk4 integrates free fall (a quadratic) exactly: the events carry only the root finder's 1e-12 s.
  const Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 2.0, 1e-3)));
  REQUIRE_FALSE(tr.failed());
  REQUIRE(tr.impacts.size() >= 20);
  CHECK(tr.impacts[0].t == Approx(t1).margin(1e-11));
  CHECK(tr.impacts[0].u_before == Approx(-v1).epsilon(1e-10));
  for (size_t k = 1; k + 1 < 16; ++k) {  // t_{k+1} - t_k = e (t_k - t_{k-1})
    const double d0 = tr.impacts[k].t - tr.impacts[k - 1].t, d1 = tr.impacts[k + 1].t - tr.impacts[k].t;
    CHECK(d1 == Approx(e * d0).margin(2e-11));
    // each impact's loss: (1 - e^2) m v^2 / 2, m = 2 kg (the effective mass of a prismatic root)
    const double v = tr.impacts[k].u_before;
    CHECK(tr.impacts[k].energy_lost == Approx(0.5 * (1 - e * e) * 2.0 * v * v).epsilon(1e-9));
  }
  const Impact& last = tr.impacts.back();
  CHECK(last.rests);
  CHECK(last.t == Approx(zeno).margin(1e-6));  // ended where the approach fell below kRestSpeed
  CHECK(last.t < zeno);
  for (size_t k = 0; k < tr.t.size(); ++k)
    if (tr.t[k] > zeno + 1e-3) {
      CHECK(tr.q[k][0] == 0.0);  // held on the stop exactly
      CHECK(tr.u[k][0] == 0.0);
    }
  // E + W_diss, the impacts' losses counted as dissipated, is constant (measured 4.2e-11 J of 19.6 J).
  for (size_t k = 0; k < tr.t.size(); ++k) CHECK(std::abs(tr.energy[k] + tr.dissipated[k] - tr.energy[0]) < 1e-9);
  CHECK(tr.dissipated.back() == Approx(2.0 * g * 1.0).epsilon(1e-9));  // all of m g h
}

TEST_CASE("a double pendulum's shoulder stops: impulses through A keep E + W_diss, and converge with the step", "[limits]") {
  const Model m = limitScene("double_stop.json");
  const Trajectory fine = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 3.0, 1e-12)));
  const Trajectory coarse = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 3.0, 1e-9)));
  const Trajectory art = simulate(m, checked(test::runSpec(Method::Articulated, Integrator::RK8PD, 3.0, 1e-12)));
  REQUIRE_FALSE(fine.failed());
  REQUIRE(fine.impact_count >= 2);
  for (size_t k = 0; k < fine.t.size(); ++k) CHECK(std::abs(fine.energy[k] + fine.dissipated[k] - fine.energy[0]) < 1e-9);
  // The elbow, not on a stop, changes speed at each impact (the tree's coupling through A).
  REQUIRE(fine.impact_count == art.impact_count);
  for (size_t i = 0; i < fine.impacts.size(); ++i) {
    CHECK(fine.impacts[i].t == Approx(art.impacts[i].t).margin(1e-9));  // two methods, one event
    if (fine.impacts[i].rests) CHECK(fine.impacts[i].u_after == 0.0);  // an approach below kRestSpeed: it rests
    else CHECK(fine.impacts[i].u_after == Approx(-0.6 * fine.impacts[i].u_before).epsilon(1e-12));
    CHECK(fine.impacts[i].t == Approx(coarse.impacts[i].t).margin(1e-6));
  }
}

TEST_CASE("joint limits run under the one-step integrators only, and no engine takes them yet", "[limits]") {
  const Model m = limitScene("slide_floor.json");
  CHECK_THROWS_WITH(simulate(m, checked(test::runSpec(Method::Classical, Integrator::IDA, 1.0, 1e-8))),
                    Catch::Contains("joint limits are events of the in-house one-step integrators"));
}
