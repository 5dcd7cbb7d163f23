#pragma once
// The other engines' methods, schemes and engines by name: their ids are
// given at run time, when reference/table.cpp adds their rows.
#include <algorithm>
#include <cmath>
#include <string>

#include <catch2/catch.hpp>

#include "compare/engines.hpp"
#include "reference/engine.hpp"
#include "io/scene_json.hpp"
#include "support.hpp"

namespace em::test {

inline Engine engine(const char* name) {
  useEngines();
  return parseEngine(name);
}
inline Method method(const char* name) {
  useEngines();
  return parseMethod(name);
}
inline Integrator scheme(const char* name) {
  useEngines();
  return parseIntegrator(name);
}

/// An engine's fixed-step scheme on a mechanism at two steps, against the
/// in-house motion (classical, projection, rk8pd 1e-12) over t_end: the
/// largest pose error and the loops' largest violation (m or rad, by our g(q))
/// at dt and dt/2. Every test of an engine's closures asks this.
struct MechanismConvergence {
  double err[2] = {0, 0}, gap[2] = {0, 0};
  bool ran = true;
};
inline MechanismConvergence mechanismConvergence(const std::string& file, const char* engine_method, const char* scheme_name,
                                                 double t_end, double dt) {
  const Model m = loadScene(sourcePath(file)).model;
  const Trajectory ref = runTrajectory(m, checked(runSpec(method("classical"), Integrator::RK8PD, t_end, 1e-12)));
  MechanismConvergence c;
  c.ran = !ref.failed();
  for (int i = 0; i < 2; ++i) {
    const Trajectory o = runTrajectory(m, checked(runSpec(method(engine_method), scheme(scheme_name), t_end, i == 0 ? dt : dt / 2)));
    c.ran = c.ran && !o.failed();
    c.err[i] = maxPoseDiff(o, ref);
    c.gap[i] = o.has_loops ? std::max(o.loops.position_m, o.loops.position_rad) : 0;
  }
  return c;
}

/// An engine's scheme on the shipped mechanisms that test closures, point
/// springs and drives (the door and plate: a weld and a hinge; A04: a
/// redundant hinge; A05: point spring-dampers), asserted first order against
/// the in-house motion over 0.5 s at dt 1e-4 and 5e-5: the pose error halves
/// (1.6 to 2.4 asserted) and the loops' opening, a step's own drift fed back
/// at ERP, falls ~4-fold (3.2 asserted). Used inside a Catch TEST_CASE.
inline void checkMechanismsFirstOrder(const char* engine_method, const char* scheme_name) {
  for (const char* file : {"tests/scenes/mechanisms/door_and_plate.json", "data/scenes/mechanisms/iftomm_a04.json",
                           "data/scenes/mechanisms/iftomm_a05.json"}) {
    const MechanismConvergence c = mechanismConvergence(file, engine_method, scheme_name, 0.5, 1e-4);
    INFO(file << ": pose error " << c.err[0] << " -> " << c.err[1] << "; loops open " << c.gap[0] << " -> " << c.gap[1]);
    REQUIRE(c.ran);
    CHECK(c.err[0] > 1.6 * c.err[1]);
    CHECK(c.err[0] < 2.4 * c.err[1]);
    if (c.gap[0] > 0) CHECK(c.gap[0] > 3.2 * c.gap[1]);
  }
}

}  // namespace em::test
