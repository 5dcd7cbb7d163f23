#pragma once
/// Work-precision: each method at several steps (rk4) or tolerances (adaptive
/// integrators) against one reference, error against CPU time.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compare/comparison.hpp"

namespace em {

struct PrecisionOptions {
  std::vector<Method> methods = {Method::Classical, Method::Eigen, Method::EigenJacobi};
  Integrator integrator = Integrator::RK4;  ///< of the in-house methods
  /// dt for rk4 (halvings that divide the 0.01 s output grid), tolerances otherwise;
  /// another engine's method runs its default integrator at the same tolerances (adaptive integrators only).
  std::vector<double> settings = {1e-2, 5e-3, 2.5e-3, 1.25e-3, 6.25e-4};
  RunSpec reference = defaultReferenceSpec();  ///< Simbody rkmerson at 1e-10 by default
  Grid grid;                           ///< t_end and output_dt asked for (absent: the scene's)
  MethodOptions options;               ///< of every point (step budget, eigen-block's delta)

  /// The run of `method` at `setting` (dt or tolerance), on no grid yet.
  RunSpec specFor(Method method, double setting) const;
};

struct PrecisionPoint {
  MethodMetrics metrics;  ///< metrics.run: the method, integrator and dt or tolerance of the point
};

struct PrecisionResult {
  std::string scene_name;
  SceneSource scene_source;
  PrecisionOptions options;
  double t_end = 0;
  Trajectory reference;
  std::vector<PrecisionPoint> points;  ///< methods x settings, in that order
};

/// Every method at every setting against one reference run. Settings are
/// checked before the reference runs.
PrecisionResult runPrecision(const Scene& scene, const PrecisionOptions& opt,
                             void (*progress)(const std::string&) = nullptr);

/// Table: method, dt or tol, status, max pose error, max energy error, CPU s, rhs evaluations.
std::string precisionTable(const PrecisionResult& r);

/// JSON (`eigenmass-precision/1`): scene, options, reference, points.
nlohmann::json precisionJson(const PrecisionResult& r);

}  // namespace em
