#pragma once
/// Work-precision: each method at several steps (rk4) or tolerances (adaptive
/// integrators) against one reference, error against CPU time.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compare/comparison.hpp"

namespace em {

struct PrecisionOptions {
  std::vector<std::string> methods = {"classical", "eigen", "eigen-jacobi"};
  std::string integrator = "rk4";
  /// dt for rk4 (halvings that divide the 0.01 s output grid), tolerances otherwise;
  /// `simbody` runs RK-Merson at the same tolerances (adaptive integrators only).
  std::vector<double> settings = {1e-2, 5e-3, 2.5e-3, 1.25e-3, 6.25e-4};
  RunSpec reference;   ///< Simbody rkmerson at 1e-10 by default
  double t_end = 0, output_dt = 0;  ///< 0: the scene's
  PrecisionOptions();
};

struct PrecisionPoint {
  std::string method, integrator;
  double setting = 0;  ///< dt or tolerance
  MethodMetrics metrics;
};

struct PrecisionResult {
  std::string scene_name;
  PrecisionOptions options;
  double t_end = 0;
  Trajectory reference;
  std::vector<PrecisionPoint> points;  ///< methods x settings, in that order
};

PrecisionResult runPrecision(const Model& m, const PrecisionOptions& opt, void (*progress)(const std::string&) = nullptr);

/// Table: method, dt or tol, status, max pose error, max energy error, CPU s, rhs evaluations.
std::string precisionTable(const PrecisionResult& r);

/// JSON (`eigenmass-precision/1`): scene, options, reference, points.
nlohmann::json precisionJson(const PrecisionResult& r);

}  // namespace em
