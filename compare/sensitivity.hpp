#pragma once
/// A reference's sensitivity check: the same run from a start kSensitivitySigma
/// away in every coordinate and speed. Where the twin parts from the reference
/// by more than an accuracy, the problem, not a method, decides errors of that
/// size: a scene at rest on an unstable equilibrium (the Allegro hand at q = 0)
/// amplifies round-off at its own rate, so a run's "error" there measures
/// round-off. Such an accuracy is ill-conditioned, and no route is ranked at it.
#include <cstdint>
#include <optional>

#include "solver/model.hpp"
#include "solver/run_spec.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// The twin's displacement: sigma N(0, 1) on every coordinate (rad, m) and
/// speed (rad/s, m/s), solver/perturb.hpp's draw with seed kSensitivitySeed.
/// 1e-10: far below every accuracy judged (1e-6 rad at the finest), far above
/// round-off (the reference's tolerance is 1e-12).
inline constexpr double kSensitivitySigma = 1e-10;
inline constexpr std::uint64_t kSensitivitySeed = 1;

struct Sensitivity {
  double sigma = kSensitivitySigma;
  double max_pose_rad = 0;          ///< the twin's largest pose difference from the reference over the horizon
  std::optional<double> failed_at;  ///< s: where the twin stopped and the reference did not (then ill-conditioned at every accuracy)
};

/// The twin of `reference`, a run of `m` by `spec`; nothing for a scene with
/// loops (a displaced start leaves them: its twin would be refused).
std::optional<Sensitivity> sensitivityTwin(const Model& m, const CheckedRunSpec& spec, const Trajectory& reference);

/// Whether the twin parts by more than `accuracy` (rad), or stopped where the reference did not.
bool illConditioned(const Sensitivity& s, double accuracy);

}  // namespace em
