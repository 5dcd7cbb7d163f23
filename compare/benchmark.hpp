#pragma once
/// A benchmark problem's error measure (docs/scene-format.md, "benchmark";
/// docs/benchmark.md): the largest |x_run - x_ref| of the scene's measured
/// point coordinates over the problem's output steps. Of two runs on one
/// grid: the steps beyond the runs' horizon (a shorter --t-end) are not measured.
#include <optional>
#include <string>
#include <vector>

#include "io/scene_json.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// A measured coordinate of every body's sample: x = p + R(quat) point, its `axis` (world).
double measuredCoordinate(const BenchmarkPoint& b, const Pose& pose);

struct BenchmarkError {
  double max_abs = 0;  ///< m: the largest |x_run - x_ref|
  double at_t = 0;     ///< when (s)
  std::string at;      ///< which coordinate (BenchmarkPoint::name)
  int steps = 0;       ///< output steps measured (those up to the run's end, when it failed)
};

/// The error of `run` against `ref` over the output steps k t_end / outputs,
/// k = 1..N, that both hold (a failed run: up to its failure). Throws
/// std::invalid_argument when a step is not a sample of both (another output
/// grid) or a measured body is in neither.
BenchmarkError benchmarkError(const BenchmarkSpec& spec, const Trajectory& run, const Trajectory& ref);

/// The same measure against the problem's own solution (spec.solution, which
/// must be present) instead of a reference run.
BenchmarkError solutionError(const BenchmarkSpec& spec, const Trajectory& run);

/// The index of `tr`'s sample at time t (within 1e-9 relative), or -1.
int sampleAt(const Trajectory& tr, double t);

}  // namespace em
