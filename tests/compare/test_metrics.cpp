// The comparator on synthetic trajectories whose errors are known exactly.
#include <catch2/catch.hpp>

#include "compare/comparison.hpp"
#include "engines.hpp"
#include "synthetic.hpp"

using namespace em;

namespace {
// Sample times are k * 0.01; the error slope 0.021 rad/s crosses 1e-3 rad
// after 0.0476 s and 0.1 rad after 4.762 s: first samples 0.05 and 4.77 s.
constexpr double kSlope = 0.021;
// Sums like 0.3 t + slope t differ from the exact error by a few ulps.
constexpr double kUlps = 1e-12;
}  // namespace

TEST_CASE("divergence times and peak errors of a run with a linearly growing error", "[comparator]") {
  const Trajectory ref = test::turning(em::test::method("simbody"), 0, 0), run = test::turning(Method::Eigen, kSlope, 0.5);
  const std::vector<std::optional<double>> no_horizon = {std::nullopt, std::nullopt};
  const MethodMetrics m = measureRun(run, ref, {1e-3, 1e-1}, no_horizon, energyScale(ref));
  REQUIRE(m.divergence_time_s[0]);
  CHECK(*m.divergence_time_s[0] == Approx(0.05));
  CHECK(*m.divergence_time_s[1] == Approx(4.77));
  CHECK(*m.coord_divergence_time_s[1] == Approx(4.77));
  CHECK(m.divergence_meaningful[0]);
  CHECK(m.pose.value == Approx(kSlope * 10).epsilon(kUlps));
  CHECK(m.pose.t == Approx(10.0));
  CHECK(m.coord.value == Approx(kSlope * 10).epsilon(kUlps));
  // Unit circle: the CM distance is the chord 2 sin(error / 2).
  CHECK(m.position.value == Approx(2 * std::sin(kSlope * 10 / 2)).epsilon(kUlps));
  // Energy scale: the reference's largest kinetic energy, 2 J; drift 0.5 J/s.
  CHECK(energyScale(ref) == 2.0);
  CHECK(m.energy.value == Approx(0.5 * 10 / 2.0).epsilon(kUlps));
  CHECK(m.energy_error_final == Approx(2.5).epsilon(kUlps));
}

TEST_CASE("a run that never crosses a threshold has no divergence time", "[comparator]") {
  const Trajectory ref = test::turning(em::test::method("simbody"), 0, 0), run = test::turning(Method::Classical, 1e-5, 0);
  const MethodMetrics m = measureRun(run, ref, {1e-3}, {std::nullopt}, 2.0);
  CHECK_FALSE(m.divergence_time_s[0]);
  CHECK_FALSE(m.divergence_meaningful[0]);
  CHECK(m.status() == Outcome::Ok);
}

TEST_CASE("a failed run diverges at its failure time and keeps its cause", "[comparator]") {
  const Trajectory ref = test::turning(em::test::method("simbody"), 0, 0);
  Trajectory run = test::turning(Method::Eigen, kSlope, 0, 3.0);  // stops at 3 s, error 0.063 rad
  markFailed(run, 3.0, Failure::EigenGap, "eigenvalue gap below the floor");
  const MethodMetrics m = measureRun(run, ref, {1e-3, 1e-1}, {std::nullopt, std::nullopt}, 2.0);
  CHECK(*m.divergence_time_s[0] == Approx(0.05));  // crossed before failing
  CHECK(*m.divergence_time_s[1] == 3.0);           // never crossed: failure time
  CHECK(m.failure == "eigenvalue gap below the floor");
  CHECK(m.series.t.size() == 301);
}

TEST_CASE("the reference horizon flags divergence times beyond it", "[comparator]") {
  const Trajectory ref = test::turning(em::test::method("simbody"), 0, 0);
  const Trajectory tight = test::turning(em::test::method("simbody"), 0.0021, 0);  // parts from ref by 1e-3 rad after 0.476 s
  const auto h = referenceHorizon(ref, tight, {1e-3, 1e-1});
  REQUIRE(h[0]);
  CHECK(*h[0] == Approx(0.48));
  CHECK_FALSE(h[1]);
  const MethodMetrics m = measureRun(test::turning(Method::Eigen, kSlope, 0), ref, {1e-3, 1e-1}, h, 2.0);
  CHECK(m.divergence_meaningful[0]);  // 0.05 < 0.48
  const MethodMetrics slow = measureRun(test::turning(Method::Classical, 0.0011, 0), ref, {1e-3, 1e-1}, h, 2.0);
  CHECK(*slow.divergence_time_s[0] == Approx(0.91));
  CHECK_FALSE(slow.divergence_meaningful[0]);  // 0.91 >= 0.48: within the reference's own uncertainty
}

TEST_CASE("energy scale falls back when the reference never moves", "[comparator]") {
  Trajectory still = test::turning(em::test::method("simbody"), 0, 0);
  for (double& k : still.kinetic) k = 0;
  CHECK(energyScale(still) == 5.0);  // |E(0)|
  for (double& e : still.energy) e = 0;
  CHECK(energyScale(still) == 1.0);
  Trajectory blown = test::turning(em::test::method("simbody"), 0, 0);
  blown.kinetic[3] = INFINITY;  // a non-finite sample carries no scale
  CHECK(energyScale(blown) == 2.0);
}

TEST_CASE("outcome: ok, wrong only before the reference horizon, failed", "[comparator]") {
  const Trajectory ref = test::turning(em::test::method("simbody"), 0, 0);
  // Error kSlope t: beyond kWrongRad = 0.1 rad from t = 4.77 s on.
  const MethodMetrics drifting = measureRun(test::turning(Method::Eigen, kSlope, 0), ref, {1e-3}, {std::nullopt}, 2.0);
  REQUIRE(drifting.status() == Outcome::Ok);
  CHECK(outcomeOf(drifting, std::nullopt) == Outcome::Wrong);  // no horizon: the whole run counts
  CHECK(outcomeOf(drifting, 6.0) == Outcome::Wrong);
  CHECK(outcomeOf(drifting, 3.0) == Outcome::Ok);  // beyond 0.1 rad only where the reference itself is uncertain
  const MethodMetrics close = measureRun(test::turning(Method::Classical, 0.001, 0), ref, {1e-3}, {std::nullopt}, 2.0);
  CHECK(outcomeOf(close, std::nullopt) == Outcome::Ok);  // 0.01 rad at most
  Trajectory stopped = test::turning(Method::Eigen, 0, 0, 3.0);
  markFailed(stopped, 3.0, Failure::NonPositiveEigenvalue, "eigenvalue lambda_0 <= 0");
  CHECK(outcomeOf(measureRun(stopped, ref, {1e-3}, {std::nullopt}, 2.0), std::nullopt) == Outcome::Failed);
}
