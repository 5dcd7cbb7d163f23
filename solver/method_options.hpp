#pragma once
/// What every in-house method is told beside its own row (solver/registry.hpp):
/// numerical-failure thresholds shared by all, and the values of the options a
/// method's row declares (MethodInfo::params) that the user set.
#include <map>
#include <string>

namespace em {

/// How a mechanism's loops are kept closed (docs/theory.md §15), one row each
/// in formulationTable() (solver/mechanism/formulation.cpp).
enum class Formulation {
  Baumgarte,   ///< multipliers at acceleration level, G u' = -c - 2 alpha G u - beta^2 g
  Projection,  ///< the same, and after every accepted step q onto g = 0 and u onto G u = 0 in A's metric
  UdwadiaKalaba,  ///< u' = a + A^(-1/2) (G A^(-1/2))^+ (b - G a), A^(-1/2) from the method's factors; Baumgarte's b
  CoordinatePartitioning,  ///< Wehage-Haug: dependent coordinates by Newton at every evaluation, re-partitioned when the pivots degrade
  AugmentedLagrangian,     ///< index-3 augmented Lagrangian, mass-orthogonal projections, the trapezoidal rule (integrator trapezoidal)
};

/// A mechanism's formulation and its options, with their defaults.
struct LoopOptions {
  Formulation formulation = Formulation::Projection;
  double alpha = 0, beta = 0;    ///< Baumgarte's (1/s): 0 and 0 integrate the raw index-1 form and show its drift
  double projection_tol = 1e-12; ///< the projection (coordinate partitioning's Newton) stops when max |g| <= this (m, rad)
  int projection_iterations = 10;  ///< Gauss-Newton (Newton) iterations at most per step (then it goes on unconverged, counted)
  /// The augmented Lagrangian's penalty alpha = penalty_ratio * 4 ||A|| / (dt^2 ||G^T G||) at the start
  /// (max diagonals), so that the iteration matrix A + (dt^2/4) alpha G^T G weighs the
  /// loops penalty_ratio times the inertia; its Newton stops when max |dq| <= al_tol
  /// (rad, m), at most al_iterations.
  /// (--al-penalty-ratio; a plan line's tuning "al_penalty_ratio".) Through A02's
  /// singular positions 1e6 converges as dt falls and the default 1e4 does not;
  /// 1e6 as the default fails the three-turn test at coarse dt (docs/results.md,
  /// "A02 through its singular positions").
  double penalty_ratio = 1e4;
  double al_tol = 1e-12;
  int al_iterations = 30;
  double loop_tol = 1e-6;        ///< a run whose loops open beyond this (m, rad) fails (loops-open)
};

struct MethodOptions {
  LoopOptions loops;  ///< where the model has loops
  double jacobi_tol = 1e-13;  ///< stop when off(C A C^T) <= tol ||A||_F
  int jacobi_max_sweeps = 50;
  double gap_floor_rel = 1e-12;  ///< fail when min |lambda_i - lambda_j| < floor * max lambda
  /// Values of the rows' own options (MethodInfo::params) by name, as set by
  /// the user (CLI, plan); an absent one takes its row's default
  /// (MethodInfo::param).
  std::map<std::string, double> params;
  double blowup_speed = 1e6;     ///< fail when max |u| exceeds this (rad/s): the run has blown up
  /// Fail when max/min squared Cholesky pivot, a lower bound on cond(A), exceeds
  /// 1/eps: u' then has no reliable digit (gimbal lock, extreme mass ratios).
  double max_pivot_ratio = 4.5e15;
  /// Refuse a fixed-step run of more steps than this before it starts (a
  /// mistyped dt); the CLI's --allow-long-run lifts it.
  double max_steps = 1e8;
  /// Refuse a run of more output samples than this before it starts: each
  /// keeps q, u and every body's pose (1e6 samples of a 5-body scene took
  /// 244 MB and a 190 MB CSV); --allow-long-run lifts it too.
  double max_samples = 1e6;
  /// Adaptive integrators: when the right-hand side fails at a trial stage (a
  /// state the step may never accept: lambda <= 0, a gap below the floor, A
  /// singular), retry the step at a quarter of its size instead of ending the
  /// run; it ends only when the step collapses (step-underflow, with the
  /// evaluation's cause). Accepted states are never retried.
  bool retry_failed_steps = true;
};

}  // namespace em
