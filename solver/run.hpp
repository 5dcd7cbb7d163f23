#pragma once
/// What one run is (RunSpec: engine and method, integrator and its step or
/// tolerance, output grid, thresholds), carried by the trajectory it makes,
/// and the checks every engine shares (settings, the output grid).
#include <functional>
#include <stdexcept>
#include <string>

#include "solver/registry.hpp"

namespace em {

/// Most residual corrections per evaluation a run may ask for (MethodOptions::refine).
constexpr int kMaxRefine = 10;

/// Numerical-failure thresholds and the correction's tolerance.
struct MethodOptions {
  double jacobi_tol = 1e-13;  ///< stop when off(C A C^T) <= tol ||A||_F
  int jacobi_max_sweeps = 50;
  double gap_floor_rel = 1e-12;  ///< fail when min |lambda_i - lambda_j| < floor * max lambda
  /// eigen-block: eigenvalues closer than this times max lambda share a block (delta);
  /// a block splits once its eigenvalues are 2 delta apart (docs/theory.md §8).
  double block_gap_rel = 3e-2;
  /// Eigenfactor methods: residual corrections per evaluation, u' += C^T Lambda^-1 C (B - A u')
  /// (docs/theory.md §8): the eigenfactors as an approximate inverse of A. 0 = as the paper.
  int refine = 0;
  double blowup_speed = 1e6;     ///< fail when max |u| exceeds this (rad/s): the run has blown up
  /// Fail when max/min squared Cholesky pivot, a lower bound on cond(A), exceeds
  /// 1/eps: u' then has no reliable digit (gimbal lock, extreme mass ratios).
  double max_pivot_ratio = 4.5e15;
  /// Refuse a fixed-step run of more steps than this before it starts (a
  /// mistyped dt); the CLI's --allow-long-run lifts it.
  double max_steps = 1e8;
  /// Adaptive integrators: when the right-hand side fails at a trial stage (a
  /// state the step may never accept: lambda <= 0, a gap below the floor, A
  /// singular), retry the step at a quarter of its size instead of ending the
  /// run; it ends only when the step collapses (step-underflow, with the
  /// evaluation's cause). Accepted states are never retried.
  bool retry_failed_steps = true;
};

/// One run, fully resolved (no "0 means the scene's"): what made a trajectory.
struct RunSpec {
  Method method = Method::Classical;
  Integrator integrator = Integrator::RK4;
  double dt = 1e-3;        ///< fixed step (fixed-step integrators)
  double tol = 1e-10;      ///< absolute and relative tolerance (adaptive; Simbody: accuracy)
  double t_end = 10.0;
  double output_dt = 0.01;
  bool diagnostics = true; ///< eigenfactor drift at every output time
  MethodOptions options;

  Engine engine() const { return info(method).engine; }
  bool fixedStep() const { return info(integrator).fixed_step; }
  /// dt or tol, whichever the integrator uses.
  double setting() const { return fixedStep() ? dt : tol; }
};

/// A run setting that cannot be used; `field` names it (t_end, output_dt, dt, tol).
struct SettingError : std::invalid_argument {
  SettingError(const std::string& field, const std::string& what)
      : std::invalid_argument(field + " " + what), field(field) {}
  std::string field;
};

/// Throws SettingError (or std::invalid_argument for a method and integrator
/// of different engines) unless `s` can be run as it stands.
void checkRunSpec(const RunSpec& s);

/// Number of output intervals: t_end / output_dt, a whole number within
/// round-off. Throws SettingError otherwise.
long outputIntervals(double t_end, double output_dt);

/// Told the time of every output sample as a run records it (progress
/// display); may be empty. Its cost counts as sampling, not integration.
using SampleObserver = std::function<void(double t)>;

/// Fixed steps per output interval: output_dt / dt, whole within round-off.
long stepsPerOutput(double output_dt, double dt);

}  // namespace em
