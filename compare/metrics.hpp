#pragma once
/// Metrics of one run against a reference on a common output grid
/// (docs/report-format.md): coordinate-free pose error, joint-coordinate error,
/// divergence times per threshold, relative energy error, cost and diagnostics.
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "solver/model.hpp"
#include "solver/text.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// Per-sample errors of a run against the reference (common grid, up to the
/// shorter of the two).
struct ErrorSeries {
  std::vector<double> t;
  std::vector<double> pose_rad;    ///< max over bodies of the angle of R_ref^T R
  std::vector<double> position_m;  ///< max over bodies of |r - r_ref| (CM)
  std::vector<double> coord_rad;   ///< max |q - q_ref| over angle coordinates (empty if not shared)
  std::vector<double> energy_rel;  ///< energy balance |E(t) + W_diss(t) - E(0)| / E_scale
};

/// A maximum and when it happened.
struct Peak {
  double value = 0, t = 0;
};

/// Everything the report says about one method.
/// A completed run that leaves the reference by more than this (pose, rad)
/// inside the reference horizon is `wrong` (outcomeOf).
constexpr double kWrongRad = 0.1;

/// How a run followed its joint controllers' targets (docs/theory.md §18): the
/// largest and the root-mean-square |q - q*(t)| over the PD-controlled
/// coordinates and the samples (rad, m for a slide), when and where the largest.
struct Tracking {
  double max = 0, rms = 0, max_t = 0;
  std::string worst;  ///< the coordinate of the largest ("shoulder_lift_joint.q0")
};

/// A run's stops against the reference's (docs/theory.md §17): its k-th
/// impact against the reference's k-th, over the first `compared`: the largest
/// gap in time and in rebound speed; how far beyond a stop it went and for how
/// long (an engine's soft or stabilized stop; 0 for exact events).
struct ImpactCheck {
  long count = 0, reference_count = 0, compared = 0;
  double time_error_max = 0, rebound_error_max = 0, overshoot_max = 0, duration_max = 0;
  double first_time_error = NAN, first_rebound_error = NAN;  ///< the first impact's alone (NaN: none to pair)
};
ImpactCheck checkImpacts(const Trajectory& run, const Trajectory& ref);

struct MethodMetrics : RunEnd {  ///< how the run ended and its cost: the trajectory's, assigned whole
  RunSpec run;  ///< what made the run (method, integrator, step or tolerance, grid)
  Outcome outcome = Outcome::Ok;  ///< outcomeOf
  double max_joint_separation = std::numeric_limits<double>::quiet_NaN();  ///< m; maximal-coordinate engines (ODE)
  Peak pose, position, coord, energy;
  bool coords_shared = false;
  double energy_error_final = 0;
  double dissipated_final = 0;  ///< W_diss at the run's last sample (J)
  std::optional<Tracking> tracking;  ///< a model with PD-controlled joints (trackingOf), else none
  long impacts = 0;                  ///< joint-limit impacts, or an engine's contact episodes
  std::optional<ImpactCheck> impact_check;  ///< a scene with joint limits: against the reference's impacts
  std::vector<std::optional<double>> divergence_time_s;        ///< per threshold (pose)
  std::vector<std::optional<double>> coord_divergence_time_s;  ///< per threshold (joint coordinates)
  std::vector<bool> divergence_meaningful;                     ///< below the reference horizon
  // Eigenfactor diagnostics (eigenfactor methods only).
  bool has_diagnostics = false;
  Peak orth_err, offdiag_rel, max_Omega, inv_err;
  EigenStats eigen;
  ErrorSeries series;

  std::string name() const { return methodName(run.method); }
};

/// Scale of the relative energy error: the largest kinetic energy of the
/// reference run (datum-free, never zero for a moving system); |E(0)| if the
/// reference never moves; 1 J if both vanish.
double energyScale(const Trajectory& ref);
/// The same with what it is: the reference's largest kinetic energy; where
/// that is round-off (below kRestKinetic of the energies' scale: a scene at
/// rest, whose reference's kinetic energy is ~1e-32 J), |E(0)|; else the
/// range of its potential energy; else 1 J.
struct EnergyScale {
  double joules = 1;
  std::string definition;
};
EnergyScale energyScaleOf(const Trajectory& ref);
inline constexpr const char* kKineticScale = "largest kinetic energy of the reference run";  ///< its usual definition
/// A kinetic energy below this share of |E(0)| or of the potential's range is round-off.
inline constexpr double kRestKinetic = 1e-12;

/// Per-sample errors of `run` against `ref`.
ErrorSeries errorSeries(const Trajectory& run, const Trajectory& ref, double energy_scale);

/// First sample time at which `err` exceeds `threshold` (nullopt if never).
std::optional<double> firstExceedance(const std::vector<double>& t, const std::vector<double>& err, double threshold);

/// Full metrics of one run. A run that failed before a threshold was crossed
/// counts as diverged at its failure time.
MethodMetrics measureRun(const Trajectory& run, const Trajectory& ref, const std::vector<double>& thresholds,
                         const std::vector<std::optional<double>>& horizon, double energy_scale);

/// A run's tracking of the PD controllers' targets of `m` (file-order
/// samples), or none where no joint is PD-controlled.
std::optional<Tracking> trackingOf(const Model& m, const Trajectory& run);

/// What a run amounts to: `failed` (stopped: status failed), `wrong`
/// (completed, but beyond kWrongRad of the reference at a sample before
/// `horizon`, the reference horizon at kWrongRad; anywhere when there is none)
/// or `ok` (completed and within kWrongRad up to the horizon).
Outcome outcomeOf(const MethodMetrics& m, const std::optional<double>& horizon);

/// Reference horizon per threshold: when the reference and a tighter run of it part.
std::vector<std::optional<double>> referenceHorizon(const Trajectory& ref, const Trajectory& tight,
                                                    const std::vector<double>& thresholds);

}  // namespace em
