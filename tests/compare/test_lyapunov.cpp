// The maximal Lyapunov exponent (compare/lyapunov.hpp): positive and stable on
// a chaotic scene, falling towards zero like ln(t) / t on a regular one, and
// independent of the twin's separation while that stays small.
#include <catch2/catch.hpp>

#include <cmath>

#include "compare/lyapunov.hpp"
#include "solver/perturb.hpp"
#include "support.hpp"

using namespace em;

TEST_CASE("the Lyapunov exponent is positive on the chaotic pendulum and tends to zero on the spherical pendulum",
          "[lyapunov]") {
  LyapunovOptions o;
  const Lyapunov chaotic = lyapunovExponent(test::loadData("pendulum5.json"), o);
  INFO("pendulum5 " << chaotic.per_s << " +- " << chaotic.uncertainty_per_s);
  REQUIRE(chaotic.ok);
  CHECK(chaotic.windows.size() == 10);
  CHECK(chaotic.per_s > 3 * chaotic.uncertainty_per_s);  // positive beyond its spread over the windows
  CHECK(chaotic.per_s > 0.5);
  // chain01 is one rigid body on a gimbal: a spherical pendulum, integrable. Twin
  // separations grow linearly, so the finite-time exponent is about ln(t) / t.
  const Model regular = test::loadData("chain01.json");
  const Lyapunov at10 = lyapunovExponent(regular, o);
  o.t_end = 100;
  const Lyapunov at100 = lyapunovExponent(regular, o);
  INFO("chain01 " << at10.per_s << " at 10 s, " << at100.per_s << " at 100 s");
  CHECK(at100.per_s < 0.1);
  CHECK(at100.per_s < 0.5 * at10.per_s);
  CHECK(at100.per_s < chaotic.per_s / 10);
}

TEST_CASE("the exponent does not depend on the twin's separation while it stays small", "[lyapunov]") {
  const Model m = test::loadData("pendulum5.json");
  LyapunovOptions o;
  const double a = lyapunovExponent(m, o).per_s;
  o.d0 = 1e-9;
  const double b = lyapunovExponent(m, o).per_s;
  CHECK(std::abs(a - b) < 0.02 * a);  // linear regime: the same exponent to 2 %
}

TEST_CASE("the exponent over several starts: the scene's own, then neighbours displaced by sigma, their mean and spread", "[lyapunov]") {
  // Issue 54 item 6: one trajectory's standard error does not say how the exponent moves between starts.
  const Model m = test::loadData("pendulum5.json");
  LyapunovOptions o;
  o.t_end = 5;
  const LyapunovStarts st = lyapunovOverStarts(m, o, 4, 1e-3);
  REQUIRE(st.starts.size() == 4);
  CHECK(st.completed == 4);
  // The first is the scene's own start; the others perturbedStart's neighbours, seeds seed + k.
  CHECK(st.starts[0].per_s == lyapunovExponent(m, o).per_s);
  std::vector<double> x = {st.starts[0].per_s};
  for (int k = 1; k < 4; ++k) {
    const Model near = perturbedStart(m, 1e-3, 1e-3, kLyapunovStartsSeed + k);
    CHECK(st.starts[k].per_s == lyapunovExponent(near, o).per_s);
    x.push_back(st.starts[k].per_s);
    // sigma per coordinate: the neighbour's start is ~sigma sqrt(n) away, not more than 6 sigma per coordinate.
    CHECK((near.q0() - m.q0()).cwiseAbs().maxCoeff() < 6e-3);
    CHECK((near.q0() - m.q0()).norm() > 1e-4);
  }
  // Mean and sample standard deviation by hand (n - 1).
  const double mean = (x[0] + x[1] + x[2] + x[3]) / 4;
  double var = 0;
  for (double v : x) var += (v - mean) * (v - mean) / 3;
  CHECK(st.mean_per_s == Approx(mean).epsilon(1e-14));
  CHECK(st.spread_per_s == Approx(std::sqrt(var)).epsilon(1e-12));
  CHECK(st.spread_per_s > 0);  // a chaotic motion's neighbours differ over 5 s
  // Deterministic: the same call, the same numbers.
  CHECK(lyapunovOverStarts(m, o, 4, 1e-3).spread_per_s == st.spread_per_s);
  // One start: the scene's exponent and no spread.
  const LyapunovStarts one = lyapunovOverStarts(m, o, 1, 1e-3);
  CHECK(one.mean_per_s == st.starts[0].per_s);
  CHECK(std::isnan(one.spread_per_s));
}
