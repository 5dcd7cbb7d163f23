#pragma once
/// Integration of one method's dynamics on an output grid: the hand-written
/// classical RK4 step and GSL odeiv2's rkf45, rk8pd and bsimp.
#include <string>

#include "solver/dynamics.hpp"
#include "solver/trajectory.hpp"

namespace em {

enum class Integrator { RK4, RKF45, RK8PD, BSIMP };

const char* integratorName(Integrator i);
bool parseIntegrator(const std::string& s, Integrator& i);
bool isFixedStep(Integrator i);

struct SimOptions {
  Integrator integrator = Integrator::RK4;
  double dt = 1e-3;        ///< fixed step (rk4)
  double tol = 1e-10;      ///< absolute and relative tolerance (adaptive integrators)
  double t_end = 10.0;
  double output_dt = 0.01;
  bool diagnostics = true; ///< eigenfactor drift at every output time
};

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

/// Simulate the model's initial state with one method; never throws on a
/// numerical failure (the trajectory carries status, time and cause).
/// Throws std::invalid_argument for inconsistent options.
Trajectory simulate(const Model& m, Method method, const SimOptions& opt, const MethodOptions& mopt = {});

/// Record the sample at time t of state y (file order) into tr.
void appendSample(Dynamics& dyn, double t, const double* y, bool diagnostics, Trajectory& tr);

}  // namespace em
