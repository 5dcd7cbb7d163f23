#pragma once
/// Integration of one in-house method on an output grid (docs/theory.md §9):
/// a fixed-step row's step function (solver/steppers.hpp) or an adaptive
/// row's GSL stepper under GSL's evolve loop. The loop owns the run's
/// counters and its first failure.
#include "solver/dynamics.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// Simulate the model's initial state as `spec` says (an in-house method and
/// integrator). Never throws on a numerical failure: the trajectory carries
/// status, time and cause. Throws SettingError or std::invalid_argument for
/// settings that cannot be run.
/// Throws std::invalid_argument for settings that cannot run on this model:
/// an integrator that steps A and B itself (ida, trapezoidal) with a method's
/// own state, trapezoidal on a quaternion joint, the augmented Lagrangian and
/// its trapezoidal rule apart on a mechanism. simulate() calls it first.
void refuseUnrunnable(const Model& m, const RunSpec& spec);

Trajectory simulate(const Model& m, const CheckedRunSpec& spec, const SampleObserver& observe = {});

}  // namespace em
