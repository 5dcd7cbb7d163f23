#pragma once
/// The CI gate: bounds on each method's pose and energy error per scene over a
/// stated horizon (data/tolerances.json, format eigenmass-tolerances/1).
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compare/comparison.hpp"

namespace em {

struct Bound {
  std::string metric;  ///< max_pose_error_rad, max_position_error_m or energy_error_max
  double value = 0;
  std::string reason;
};

struct SceneTolerances {
  double horizon_s = 0;
  RunSpec inhouse;  ///< integrator and dt/tol the bounds were set for (in-house methods)
  std::map<std::string, std::vector<Bound>> methods;
};

struct Tolerances {
  std::map<std::string, SceneTolerances> scenes;
};

/// Load and validate a tolerance file; errors name the file and the JSON path.
Tolerances loadTolerances(const std::string& path);

struct GateCheck {
  std::string method, metric, reason, note;
  double value = 0, bound = 0, horizon_s = 0;
  bool passed = false;
};

struct GateResult {
  bool passed = true;
  std::vector<GateCheck> checks;
};

/// Evaluate every bound of the comparison's scene over t <= horizon_s. A method
/// not run is skipped; a failed method, a run shorter than the horizon or one
/// made with other integrator settings than the file states breaks its bounds.
GateResult evaluateGate(const ComparisonResult& r, const Tolerances& tol);

nlohmann::json gateJson(const GateResult& g);

/// The broken checks, one line each.
std::string brokenChecks(const GateResult& g);

}  // namespace em
