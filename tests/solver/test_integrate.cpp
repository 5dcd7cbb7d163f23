// Integrators: the hand-written RK4 step (exactly four evaluations, a
// hand-computed step), GSL's rk4 is not that, energy conservation and
// dissipation over long runs, quaternion norm, options and determinism.
#include <catch2/catch.hpp>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "solver/integrate.hpp"
#include "solver/mechanism/formulation.hpp"
#include "solver/steppers.hpp"
#include "support.hpp"

using namespace em;

namespace {

double maxRelEnergyError(const Trajectory& t) {
  double e = 0;
  for (double E : t.energy) e = std::max(e, std::abs(E - t.energy[0]) / std::abs(t.energy[0]));
  return e;
}

// One body turning about z at its CM, no gravity, no spring, a damper c.
Model dampedRotor(double I, double c, double u0) {
  SceneSpec s;
  s.name = "rotor";
  s.gravity = Vec3::Zero();
  BodySpec b;
  b.name = "rotor";
  b.parent = "ground";
  b.inertia = Vec3(1.0, 1.0, I).asDiagonal();
  b.joint.axis[0] = Vec3::UnitZ();
  b.joint.q0 = Eigen::VectorXd::Zero(1);
  b.joint.u0 = Eigen::VectorXd::Constant(1, u0);
  b.joint.has_spring = true;
  b.joint.spring = {Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, c), Eigen::VectorXd::Zero(1)};
  s.bodies.push_back(b);
  return buildModel(s);
}

int countingRhs(double, const double y[], double dydt[], void* calls) {
  ++*static_cast<int*>(calls);
  dydt[0] = -2.0 * y[0];
  return GSL_SUCCESS;
}

}  // namespace

TEST_CASE("rk4Step evaluates four times and matches the hand-computed step", "[closedform][integrate]") {
  // y' = -2 y: one RK4 step multiplies y by 1 + z + z^2/2 + z^3/6 + z^4/24, z = -2 h.
  int calls = 0;
  auto f = [&calls](double, const double* y, double* dy) {
    ++calls;
    dy[0] = -2.0 * y[0];
    return true;
  };
  double y = 1.5;
  StepScratch w(1);
  const double h = 0.1, z = -2 * h;
  REQUIRE(rk4Step(Derivative(f), 0.0, h, &y, 1, w));
  CHECK(calls == 4);
  CHECK(std::abs(y - 1.5 * (1 + z + z * z / 2 + z * z * z / 6 + z * z * z * z / 24)) < 1e-15);
}

TEST_CASE("GSLs rk4 stepper is not one classical step: it does step doubling", "[closedform][integrate]") {
  // The reason rk4 is hand-written: gsl_odeiv2_step_rk4 spends 11 evaluations
  // per step and returns two half steps.
  int calls = 0;
  gsl_odeiv2_system sys{countingRhs, nullptr, 1, &calls};
  gsl_odeiv2_step* s = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk4, 1);
  double y = 1.5, err;
  gsl_odeiv2_step_apply(s, 0.0, 0.1, &y, &err, nullptr, nullptr, &sys);
  gsl_odeiv2_step_free(s);
  CHECK(calls == 11);
  const double z = -0.2, one = 1 + z + z * z / 2 + z * z * z / 6 + z * z * z * z / 24;
  CHECK(std::abs(y - 1.5 * one) > 1e-7);  // not the single classical step
}

TEST_CASE("simulate with rk4 takes t_end/dt steps of four evaluations each", "[integrate]") {
  const Model m = test::loadData("chain03.json");
  const Trajectory t = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 0.5, 1e-3)));
  CHECK(t.steps == 500);
  CHECK(t.rhs_evals == 4 * 500);
  CHECK(t.size() == 51);
  CHECK(t.t.back() == Approx(0.5).epsilon(1e-15));
}

TEST_CASE("pendulum5 classical rk8pd tol 1e-12 10 s: energy conserved to 1e-10", "[integrate][energy]") {
  const Model m = test::loadData("pendulum5.json");
  const Trajectory t = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 10.0, 1e-12)));
  REQUIRE(t.status() == Outcome::Ok);
  REQUIRE(t.size() == 1001);
  CHECK(maxRelEnergyError(t) < 1e-10);
}

TEST_CASE("with dampers the energy never increases", "[integrate][energy]") {
  const Model m = test::loadData("spring_damper.json");
  const Trajectory t = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 5.0, 1e-12)));
  REQUIRE(t.status() == Outcome::Ok);
  // Allowance per sample: the integration error of a tol-1e-12 run, far below
  // the dissipation per sample (~1e-3 J here).
  const double kAllowance = 1e-9 * std::abs(t.energy[0]);
  for (size_t k = 1; k < t.size(); ++k) CHECK(t.energy[k] <= t.energy[k - 1] + kAllowance);
  CHECK(t.energy.back() < t.energy[0] - 0.1);  // and it does dissipate
}

TEST_CASE("a damped rotor: u and W_diss follow their closed forms", "[closedform][integrate][energy]") {
  // One body turning about z at its CM, no gravity, no spring, damper c:
  // I u' = -c u, so u = u0 e^(-c t / I) and W_diss = I u0^2 (1 - e^(-2 c t / I)) / 2.
  const double I = 2.0, c = 0.5, u0 = 3.0;
  const Model m = dampedRotor(I, c, u0);
  REQUIRE(m.has_dampers);
  const Trajectory t = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 4.0, 1e-12, 0.5)));
  REQUIRE(t.status() == Outcome::Ok);
  const double E0 = 0.5 * I * u0 * u0;  // 9 J
  for (size_t k = 0; k < t.size(); ++k) {
    const double decay = std::exp(-2 * c * t.t[k] / I);
    // tol 1e-12 on values of order 1-10: the global error stays below 1e-10 of E0.
    CHECK(std::abs(t.dissipated[k] - E0 * (1 - decay)) < 1e-10 * E0);
    CHECK(std::abs(t.energy[k] + t.dissipated[k] - E0) < 1e-10 * E0);
  }
  CHECK(t.dissipated.back() > 0.6 * E0);  // the test is not vacuous: most of E0 is gone
}

TEST_CASE("without dampers no W_diss state is integrated", "[integrate][energy]") {
  const Model m = test::loadData("pendulum5.json");
  REQUIRE(!m.has_dampers);
  const Trajectory t = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 0.1, 1e-3)));
  for (double w : t.dissipated) CHECK(w == 0.0);
}

TEST_CASE("ball quaternions stay unit and agree with the gimbal-rooted pendulum", "[integrate][identity]") {
  const Trajectory b = simulate(test::loadData("pendulum5_ball.json"), checked(test::runSpec(Method::Classical, Integrator::RK8PD, 2.0, 1e-12)));
  const Trajectory g = simulate(test::loadData("pendulum5.json"), checked(test::runSpec(Method::Classical, Integrator::RK8PD, 2.0, 1e-12)));
  REQUIRE(b.status() == Outcome::Ok);
  double pose = 0;
  for (size_t k = 0; k < b.size(); ++k) {
    CHECK(std::abs(b.q[k].head<4>().norm() - 1) < 1e-15);
    for (size_t i = 0; i < b.poses[k].size(); ++i) pose = std::max(pose, (b.poses[k][i].p - g.poses[k][i].p).norm());
  }
  CHECK(pose < 1e-8);
}

TEST_CASE("every integrator agrees on pendulum5 over 1 s", "[integrate][identity]") {
  const Model m = test::loadData("pendulum5.json");
  const Trajectory ref = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 1.0, 1e-13)));
  for (auto [i, p, bound] : {std::tuple{Integrator::RK4, 1e-3, 1e-8}, std::tuple{Integrator::RKF45, 1e-10, 1e-7},
                             std::tuple{Integrator::BSIMP, 1e-10, 1e-7}}) {
    const Trajectory t = simulate(m, checked(test::runSpec(Method::Classical, i, 1.0, p)));
    INFO(integratorName(i));
    REQUIRE(t.status() == Outcome::Ok);
    CHECK((t.q.back() - ref.q.back()).cwiseAbs().maxCoeff() < bound);
  }
}

TEST_CASE("the eigenfactor methods run under the adaptive integrators too", "[integrate][identity]") {
  const Model m = test::loadData("pendulum5.json");
  const Trajectory ref = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 1.0, 1e-12)));
  for (Method meth : {Method::Eigen, Method::EigenJacobi})
    for (Integrator i : {Integrator::RKF45, Integrator::RK8PD}) {
      const Trajectory t = simulate(m, checked(test::runSpec(meth, i, 1.0, 1e-10)));
      INFO(methodName(meth) << " " << integratorName(i));
      REQUIRE(t.status() == Outcome::Ok);
      CHECK((t.q.back() - ref.q.back()).cwiseAbs().maxCoeff() < 1e-6);
    }
}

TEST_CASE("inconsistent options are rejected before any computation", "[integrate]") {
  const Model m = test::loadData("chain01.json");
  CHECK_THROWS_AS(simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 0.003))), std::invalid_argument);
  RunSpec o = test::runSpec(Method::Classical, Integrator::RK8PD, 1.0, 0.0);
  CHECK_THROWS_AS(simulate(m, checked(o)), std::invalid_argument);
  o = test::runSpec(Method::Classical, Integrator::RK4, 1.0, 1e-3);
  o.output_dt = 0.3;
  CHECK_THROWS_AS(simulate(m, checked(o)), std::invalid_argument);
}

TEST_CASE("the same scene and options give bitwise the same numbers", "[integrate]") {
  const Model m = test::loadData("tree_mixed.json");
  for (Method meth : {Method::Classical, Method::EigenJacobi}) {
    const Trajectory a = simulate(m, checked(test::runSpec(meth, Integrator::RKF45, 0.5, 1e-9)));
    const Trajectory b = simulate(m, checked(test::runSpec(meth, Integrator::RKF45, 0.5, 1e-9)));
    CHECK(a.q == b.q);
    CHECK(a.u == b.u);
    CHECK(a.energy == b.energy);
  }
}

TEST_CASE("the hand-written rk4 converges at fourth order", "[integrate][closedform]") {
  // Halving dt must divide the error by 2^4: the observed order over two
  // halvings lies in [3.7, 4.3] (the leading term dominates at these steps).
  const Model m = test::loadData("chain03.json");
  const Trajectory ref = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 1.0, 1e-14)));
  std::vector<double> err;
  for (double dt : {0.02, 0.01, 0.005}) {
    const Trajectory t = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, dt, 0.02)));
    err.push_back((t.q.back() - ref.q.back()).cwiseAbs().maxCoeff());
  }
  for (int k = 0; k < 2; ++k) {
    const double order = std::log2(err[k] / err[k + 1]);
    INFO("dt halving " << k << ": errors " << err[k] << " -> " << err[k + 1]);
    CHECK(order > 3.7);
    CHECK(order < 4.3);
  }
}


TEST_CASE("cvode (BDF) follows the damped rotor's closed form, sampled at the output times by interpolation", "[closedform][integrate]") {
  const double I = 2.0, c = 0.5, u0 = 3.0;
  const Model m = dampedRotor(I, c, u0);
  const Trajectory t = simulate(m, checked(test::runSpec(Method::Classical, Integrator::CVODE, 4.0, 1e-10, 0.1)));
  REQUIRE(t.status() == Outcome::Ok);
  REQUIRE(t.size() == 41);
  double worst = 0;
  for (size_t k = 0; k < t.size(); ++k) {
    CHECK(t.t[k] == k * 0.1);  // the output times themselves, not the steps' ends
    worst = std::max(worst, std::abs(t.u[k][0] - u0 * std::exp(-c * t.t[k] / I)));
  }
  // tol 1e-10 (relative and absolute) on u ~ 1: BDF's global error is a few
  // tolerances over 4 s; 1e-8 leaves room and fails an order-1 mistake
  // (e.g. a Jacobian of the wrong sign costs convergence, not accuracy, but
  // a sample off by one step is ~u0 c dt / I = 0.07 off).
  CHECK(worst < 1e-8);
  CHECK(t.steps < t.rhs_evals);
}

TEST_CASE("cvode agrees with rk8pd on pendulum5 and on a mechanism under Udwadia-Kalaba", "[integrate][identity]") {
  for (const char* scene : {"pendulum5.json", "mechanisms/iftomm_a02_n2.json"}) {
    const Model m = test::loadData(scene);
    RunSpec r = test::runSpec(Method::Classical, Integrator::RK8PD, 1.0, 1e-13);
    RunSpec b = test::runSpec(Method::Classical, Integrator::CVODE, 1.0, 1e-11);
    r.options.loops.formulation = b.options.loops.formulation = Formulation::UdwadiaKalaba;
    const Trajectory ref = simulate(m, checked(r)), t = simulate(m, checked(b));
    INFO(scene);
    REQUIRE(t.status() == Outcome::Ok);
    // Both with the same unstabilized formulation: the gap is the BDF's global
    // error at 1e-11 over 1 s (measured 1e-9 and below).
    CHECK((t.q.back() - ref.q.back()).cwiseAbs().maxCoeff() < 1e-7);
  }
}

TEST_CASE("cvode on a stiff spring-damper (IFToMM A05): the benchmark's finer level in a fraction of rk8pd's evaluations", "[integrate]") {
  const Model m = test::loadData("mechanisms/iftomm_a05.json");
  const Trajectory ref = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 2.0, 1e-11)));
  const Trajectory rk = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 2.0, 1e-8)));
  const Trajectory bdf = simulate(m, checked(test::runSpec(Method::Classical, Integrator::CVODE, 2.0, 1e-8)));
  REQUIRE(ref.status() == Outcome::Ok);
  REQUIRE(bdf.status() == Outcome::Ok);
  double worst = 0;
  for (size_t k = 0; k < ref.size(); ++k) worst = std::max(worst, std::abs(bdf.q[k][1] - ref.q[k][1]));  // the slider's s
  CHECK(worst < 1e-5);  // A05's finer precision level (m)
  // The springs' time constant (c/k = 0.05 s against eigenvalues near -1e4 /s)
  // holds an explicit scheme to its stability bound: rk8pd needs >5x more.
  INFO("evaluations: cvode " << bdf.rhs_evals << ", rk8pd " << rk.rhs_evals);
  CHECK(5 * bdf.rhs_evals < rk.rhs_evals);
}

TEST_CASE("cvode refuses what corrects the state between its steps, naming it", "[integrate]") {
  const Model tree = test::loadData("pendulum5.json");
  const auto why = [](const Model& m, RunSpec s) {
    try {
      simulate(m, checked(s));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  CHECK_THAT(why(tree, test::runSpec(Method::EigenJacobi, Integrator::CVODE, 0.1, 1e-8)),
             Catch::Contains("multistep") && Catch::Contains("eigen-jacobi"));
  CHECK_THAT(why(tree, test::runSpec(Method::EigenBlock, Integrator::CVODE, 0.1, 1e-8)), Catch::Contains("eigen-block"));
  CHECK(why(tree, test::runSpec(Method::Eigen, Integrator::CVODE, 0.1, 1e-8)).empty());
  const Model mech = test::loadData("mechanisms/iftomm_a02_n2.json");
  for (Formulation f : {Formulation::Projection, Formulation::CoordinatePartitioning}) {
    RunSpec s = test::runSpec(Method::Classical, Integrator::CVODE, 0.1, 1e-8);
    s.options.loops.formulation = f;
    CHECK_THAT(why(mech, s), Catch::Contains(formulationName(f)));
  }
}
