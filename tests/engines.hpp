#pragma once
// The other engines' methods, schemes and engines by name: their ids are
// given at run time, when engines/table.cpp adds their rows.
#include <algorithm>
#include <cmath>
#include <string>

#include "compare/engines.hpp"
#include "engines/engine.hpp"
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

}  // namespace em::test
