#pragma once
/// The in-house integrators' steps (docs/theory.md §9), one function or GSL
/// stepper per row of the integrator table (solver/registry.hpp): a
/// fixed-step scheme is one function taking exactly one step of h; an
/// adaptive one is a GSL odeiv2 stepper driven by GSL's evolve loop
/// (solver/integrate.cpp). Depends on nothing of ours.
#include <type_traits>

#include <gsl/gsl_odeiv2.h>

#include <Eigen/Core>

namespace em {

/// The right-hand side a step calls: f(t, y, dydt), false when it fails.
/// A non-owning reference to any callable (no allocation, one indirect call).
class Derivative {
 public:
  template <class F, class = std::enable_if_t<!std::is_same_v<F, Derivative>>>
  explicit Derivative(F& f)
      : object_(&f), call_([](void* o, double t, const double* y, double* dy) { return (*static_cast<F*>(o))(t, y, dy); }) {}
  bool operator()(double t, const double* y, double* dydt) const { return call_(object_, t, y, dydt); }

 private:
  void* object_;
  bool (*call_)(void*, double, const double*, double*);
};

/// Scratch of a fixed step: stage derivatives and a stage state, each of the
/// state size, sized once per run.
struct StepScratch {
  explicit StepScratch(int n) : k1(n), k2(n), k3(n), k4(n), tmp(n) {}
  Eigen::VectorXd k1, k2, k3, k4, tmp;  // (n)
};

/// A fixed-step scheme: advance y (n) from t by exactly h; false if f fails.
using FixedStep = bool (*)(const Derivative& f, double t, double h, double* y, int n, StepScratch& w);

/// Classical four-stage Runge–Kutta step of exactly h: four evaluations
/// (docs/theory.md §9, eq. (RK4)).
inline bool rk4Step(const Derivative& f, double t, double h, double* y, int n, StepScratch& w) {
  double *k1 = w.k1.data(), *k2 = w.k2.data(), *k3 = w.k3.data(), *k4 = w.k4.data(), *tmp = w.tmp.data();
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

/// An adaptive scheme: GSL's stepper (the address of GSL's global, e.g. &gsl_odeiv2_step_rk8pd).
using GslStepper = const gsl_odeiv2_step_type* const*;

}  // namespace em
