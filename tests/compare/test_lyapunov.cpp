// The maximal Lyapunov exponent (compare/lyapunov.hpp): positive and stable on
// a chaotic scene, falling towards zero like ln(t) / t on a regular one, and
// independent of the twin's separation while that stays small.
#include <catch2/catch.hpp>

#include "compare/lyapunov.hpp"
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
