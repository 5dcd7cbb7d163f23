#pragma once
/// Ensembles of a plan (docs/sweep.md, "ensemble"): members of each scene whose
/// initial coordinates and speeds are perturbed reproducibly, each joint as its
/// kind allows, so that a divergence time of a chaotic scene is read as a
/// distribution; and the distributions the merge writes.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "solver/model.hpp"

namespace em {

/// A published breakdown time the members' distribution is held against
/// (the paper's 7.2 s): figures mark it, the claims page places it.
struct EnsembleClaim {
  double t_s = 0;     ///< the time, s, within the plan's t_end
  std::string label;  ///< how figures name it ("the paper's 7.2 s"), one printable line
};

/// The plan key "ensemble": {"count": N, "seed": S, "perturb": {"q": sigma_q, "u": sigma_u},
/// "claim": {"t_s": T, "label": L}}.
struct Ensemble {
  int count = 1;           ///< members per scene; member 0 is the scene itself
  std::uint64_t seed = 1;  ///< with the member's index, the one source of its draws
  double sigma_q = 0;      ///< standard deviation of each angle (rad; a ball's rotation vector)
  double sigma_u = 0;      ///< standard deviation of each speed (rad/s)
  std::optional<EnsembleClaim> claim;  ///< absent: no time is marked
};

/// Member `k` of `m`'s ensemble. Member 0 is `m`. Member k > 0 draws standard
/// normal numbers n from (seed, k) alone (SplitMix64 and Box–Muller: the same
/// on every machine), body by body in file order: every angle q += sigma_q n;
/// a ball's quaternion is turned by the rotation vector sigma_q (n1, n2, n3)
/// applied in its body frame (it stays a unit quaternion); every speed
/// u += sigma_u n.
Model ensembleMember(const Model& m, const Ensemble& e, int k);

/// Every standard normal draw lies within this (Box–Muller from 53-bit
/// uniforms: sqrt(-2 ln 2^-53) = 8.57), so member k's every coordinate lies
/// within kDrawBound sigma of the scene's.
inline constexpr double kDrawBound = 8.6;

/// Where some member of `m`'s ensemble could leave the state bounds
/// (solver/model.hpp's kMaxAngle, kMaxDisplacement, kMaxSpeed): the state of
/// |q0| + kDrawBound sigma_q and |u0| + kDrawBound sigma_u is checked, "" when
/// within (beyondStateBounds' words otherwise). Plans check it before any case runs.
std::string ensembleBeyondBounds(const Model& m, const Ensemble& e);

/// Quantiles of `x` (sorted inside) by linear interpolation between order
/// statistics (Hyndman–Fan type 7, numpy's default; GSL's
/// gsl_stats_quantile_from_sorted_data); nullopt for no values. A censored
/// member is +inf ("later than t_end"): a quantile that reaches one is +inf,
/// never interpolated (tools/ensemble_summary.py's quantile, the same convention).
std::optional<double> quantile(std::vector<double> x, double p);

/// The distribution-free interval of the median from the order statistics:
/// the widest symmetric pair (x_(l), x_(n+1-l)) whose exact Binomial(n, 1/2)
/// coverage is at least `level` (GSL's gsl_cdf_binomial_P); +inf entries are
/// censored members, as in quantile. nullopt for no values. With n <= 5 no
/// pair reaches 95 %: the pair is (min, max), covering 1 - 2^(1-n) (93.8 % at n = 5).
std::optional<std::pair<double, double>> medianInterval(std::vector<double> x, double level = 0.95);

}  // namespace em
