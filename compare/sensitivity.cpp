#include "compare/sensitivity.hpp"

#include <algorithm>

#include "compare/engines.hpp"
#include "compare/metrics.hpp"
#include "solver/perturb.hpp"

namespace em {

std::optional<Sensitivity> sensitivityTwin(const Model& m, const CheckedRunSpec& spec, const Trajectory& reference) {
  if (!m.loops.empty()) return std::nullopt;
  const Trajectory twin =
      runTrajectory(perturbedStart(m, kSensitivitySigma, kSensitivitySigma, kSensitivitySeed), spec);
  Sensitivity s;
  const ErrorSeries e = errorSeries(twin, reference, energyScale(reference));
  for (double x : e.pose_rad) s.max_pose_rad = std::max(s.max_pose_rad, x);
  if (twin.failed() && !reference.failed()) s.failed_at = twin.failure_time;
  return s;
}

bool illConditioned(const Sensitivity& s, double accuracy) {
  return s.failed_at || s.saturated() || s.roundoffPoseRad() > kRoundoffShare * accuracy;
}

}  // namespace em
