#pragma once
/// A reference's sensitivity check: the same run from a start kSensitivitySigma
/// away in every coordinate and speed. Where round-off, amplified as the twin
/// is, reaches an accuracy, the problem, not a method, decides errors of that
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
/// 1e-10: far above round-off, so the twin's gap is the motion's amplification
/// of a start's error and not the steps' noise (the reference's tolerance is
/// 1e-12), and small enough to stay linear over most horizons.
inline constexpr double kSensitivitySigma = 1e-10;
inline constexpr std::uint64_t kSensitivitySeed = 1;
/// The round-off a run's state carries (relative): 100 times double's 1.1e-16,
/// for the rounding a reference accumulates over its thousands of steps.
inline constexpr double kRoundoffScale = 1e-14;
/// Beyond this gap (rad) the twin has left the linear regime: its gap / sigma
/// is then only a lower bound of the amplification.
inline constexpr double kTwinLinearRad = 1e-2;
/// An accuracy is ill-conditioned where round-off, amplified, exceeds this
/// share of it (as a reference check's floor is judged against a tenth).
inline constexpr double kRoundoffShare = 0.1;

/// The sensitivity at round-off's scale (issue 75, item 2): the twin's gap is
/// scaled from sigma to kRoundoffScale by the linear amplification
/// A = max_pose_rad / sigma. The Z1's twin parted by 8.18e-6 rad: A = 8.2e4,
/// so round-off grows to ~8e-10 rad, and 1e-6 rad is resolved (the raw gap
/// called it ill-conditioned, six orders too coarse).
struct Sensitivity {
  double sigma = kSensitivitySigma;
  double max_pose_rad = 0;          ///< the twin's largest pose difference from the reference over the horizon
  std::optional<double> failed_at;  ///< s: where the twin stopped and the reference did not (then ill-conditioned at every accuracy)
  double amplification() const { return max_pose_rad / sigma; }
  /// What round-off (kRoundoffScale) grows to over the horizon, rad: A times the scale.
  double roundoffPoseRad() const { return amplification() * kRoundoffScale; }
  /// The twin left the linear regime (max_pose_rad > kTwinLinearRad): A is a lower bound.
  bool saturated() const { return max_pose_rad > kTwinLinearRad; }
};

/// The twin of `reference`, a run of `m` by `spec`; nothing for a scene with
/// loops (a displaced start leaves them: its twin would be refused).
std::optional<Sensitivity> sensitivityTwin(const Model& m, const CheckedRunSpec& spec, const Trajectory& reference);

/// Whether round-off, amplified as the twin measures, exceeds kRoundoffShare of
/// `accuracy` (rad); or the twin saturated (every accuracy: its amplification
/// is unknown, at least gap / sigma), or stopped where the reference did not.
bool illConditioned(const Sensitivity& s, double accuracy);

}  // namespace em
