#pragma once
/// Integration of one in-house method on an output grid (docs/theory.md §9):
/// the hand-written classical RK4 step and GSL odeiv2's rkf45, rk8pd and
/// bsimp. The loop owns the run's counters and its first failure.
#include "solver/dynamics.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// One classical four-stage Runge–Kutta step of exactly h: four evaluations.
/// k1..k4, tmp are scratch of the state size. Returns false if f fails.
template <class F>
bool rk4Step(F&& f, double t, double h, double* y, int n, double* k1, double* k2, double* k3, double* k4,
             double* tmp) {
  if (!f(t, y, k1)) return false;
  for (int i = 0; i < n; ++i) tmp[i] = y[i] + 0.5 * h * k1[i];
  if (!f(t + 0.5 * h, tmp, k2)) return false;
  for (int i = 0; i < n; ++i) tmp[i] = y[i] + 0.5 * h * k2[i];
  if (!f(t + 0.5 * h, tmp, k3)) return false;
  for (int i = 0; i < n; ++i) tmp[i] = y[i] + h * k3[i];
  if (!f(t + h, tmp, k4)) return false;
  for (int i = 0; i < n; ++i) y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  return true;
}

/// Simulate the model's initial state as `spec` says (an in-house method and
/// integrator). Never throws on a numerical failure: the trajectory carries
/// status, time and cause. Throws SettingError or std::invalid_argument for
/// settings that cannot be run.
Trajectory simulate(const Model& m, const RunSpec& spec, const SampleObserver& observe = {});

}  // namespace em
