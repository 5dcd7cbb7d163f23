#pragma once
/// The finite-time maximal Lyapunov exponent of a scene's motion (docs/theory.md
/// §11): Benettin's renormalized twin. Why a chaotic scene's divergence times
/// are what they are: an error e(t0) grows to theta at about
/// t0 + ln(theta / e(t0)) / lambda.
#include <cstdint>
#include <vector>

#include "solver/model.hpp"
#include "solver/run_spec.hpp"

namespace em {

struct LyapunovOptions {
  double t_end = 10;      ///< horizon (s)
  double dt = kDefaultDt; ///< the twin pair's rk4 step (s)
  double renorm_s = 0.1;  ///< the twin is pulled back to distance d0 this often (s)
  double window_s = 1;    ///< the uncertainty is the spread of the exponent over windows this long (s)
  double d0 = 1e-8;       ///< separation of the twin in the state (q, u), Euclidean
};

struct Lyapunov {
  double per_s = 0;              ///< lambda over [0, t_end]: sum of ln(d / d0) / t_end
  double uncertainty_per_s = 0;  ///< standard error of the window means (std / sqrt(windows)): NaN for one window
  double windows_std_per_s = 0;  ///< spread (std) of the windows' finite-time exponents: NaN for one window
  std::vector<double> windows;   ///< lambda of each window (per s)
  bool ok = true;                ///< false when a run of the pair failed (the exponent then covers [0, t_stop])
  double t_stop = 0;             ///< where the pair stopped (t_end when ok)
};

/// The exponent of `m` from its initial state: the classical method under rk4
/// carries the state and a twin displaced by d0 along a fixed direction of
/// the speeds; every renorm_s the twin's separation d is measured over (q, u)
/// and scaled back to d0 (quaternions re-normalized). Deterministic.
Lyapunov lyapunovExponent(const Model& m, const LyapunovOptions& o = {});

/// The exponent over several starts (docs/theory.md §11): one trajectory's
/// exponent, and its standard error along that trajectory, do not say how
/// much the exponent moves between neighbouring starts. The scene's own start
/// and starts - 1 neighbours, each q0 and u0 displaced by sigma
/// (perturbedStart, seeds seed + 1, seed + 2, ...), each measured as `o` says.
struct LyapunovStarts {
  double sigma = 0;
  std::uint64_t seed = 0;
  std::vector<Lyapunov> starts;  ///< [0]: the scene's own start
  int completed = 0;             ///< starts whose twin ran the whole horizon
  double mean_per_s = 0;         ///< mean over the completed starts (NaN for none)
  double spread_per_s = 0;       ///< their sample standard deviation (NaN for fewer than two)
};
inline constexpr int kLyapunovStartsMax = 64;
inline constexpr std::uint64_t kLyapunovStartsSeed = 1;

LyapunovStarts lyapunovOverStarts(const Model& m, const LyapunovOptions& o, int starts, double sigma,
                                  std::uint64_t seed = kLyapunovStartsSeed);

/// The long-run exponent (docs/theory.md §11): the same twin over `horizon_s`
/// (well beyond a run's grid), its uncertainty the standard error of 10-s
/// block means, a window long enough that neighbouring blocks are nearly
/// independent. Its options, for the report.
LyapunovOptions longRunOptions(double horizon_s);

}  // namespace em
