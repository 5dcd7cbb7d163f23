#include "compare/benchmark.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "solver/rotation.hpp"
#include "solver/text.hpp"

namespace em {

double measuredCoordinate(const BenchmarkPoint& b, const Pose& pose) {
  return (pose.p + quatToMatrix(pose.quat) * b.point)[b.axis];
}

int sampleAt(const Trajectory& tr, double t) {
  const double tol = 1e-9 * std::max(1.0, std::abs(t));
  const auto it = std::lower_bound(tr.t.begin(), tr.t.end(), t - tol);
  if (it == tr.t.end() || *it > t + tol) return -1;
  return static_cast<int>(it - tr.t.begin());
}

namespace {

int bodyIndex(const Trajectory& tr, const std::string& body, const char* which) {
  const auto it = std::find(tr.body_names.begin(), tr.body_names.end(), body);
  if (it == tr.body_names.end())
    throw std::invalid_argument(std::string("benchmark: the ") + which + " has no body '" + body + "'");
  return static_cast<int>(it - tr.body_names.begin());
}

}  // namespace

namespace {

// The measure (header) against `ref`, or against the spec's solution when `ref` is null.
BenchmarkError measureSteps(const BenchmarkSpec& spec, const Trajectory& run, const Trajectory* ref) {
  BenchmarkError e;
  std::vector<std::pair<int, int>> bodies;  // per measured coordinate: its body in run and in ref
  for (const BenchmarkPoint& b : spec.measure)
    bodies.emplace_back(bodyIndex(run, b.body, "run"), ref ? bodyIndex(*ref, b.body, "reference") : -1);
  const double step = spec.outputStep();
  const double horizon = ref ? std::min(run.run.t_end, ref->run.t_end) : run.run.t_end;
  for (int k = 1; k <= spec.outputs; ++k) {
    const double t = k * step;
    if (t > horizon * (1 + 1e-12)) break;  // a shorter horizon than the problem's
    const int i = sampleAt(run, t), j = ref ? sampleAt(*ref, t) : 0;
    if ((i < 0 && run.failed()) || (j < 0 && ref->failed())) break;  // measured up to the failure (of the run or the reference)
    if (i < 0 || j < 0)
      throw std::invalid_argument("benchmark: output step " + std::to_string(k) + " (t = " + gnum(t) + " s) is not a sample of the " +
                                  (i < 0 ? "run" : "reference") + ": its output grid must divide t_end / outputs = " + gnum(step) + " s");
    for (size_t m = 0; m < spec.measure.size(); ++m) {
      const double x_ref = ref ? measuredCoordinate(spec.measure[m], ref->poses[j][bodies[m].second]) : spec.solutionAt(k, m);
      const double d = std::abs(measuredCoordinate(spec.measure[m], run.poses[i][bodies[m].first]) - x_ref);
      if (!(d <= e.max_abs) && !std::isnan(e.max_abs)) {  // NaN, once met, stays: the run has no such digit
        e.max_abs = d;
        e.at_t = t;
        e.at = spec.measure[m].name;
      }
    }
    ++e.steps;
  }
  return e;
}

}  // namespace

BenchmarkError benchmarkError(const BenchmarkSpec& spec, const Trajectory& run, const Trajectory& ref) {
  return measureSteps(spec, run, &ref);
}

BenchmarkError solutionError(const BenchmarkSpec& spec, const Trajectory& run) {
  if (!spec.hasSolution()) throw std::invalid_argument("benchmark: problem " + spec.problem + " states no solution");
  return measureSteps(spec, run, nullptr);
}

}  // namespace em
