#pragma once
/// The one output-grid loop of every fixed-step engine (MuJoCo, and the
/// engines to come): exact multiples of dt, one failure rule checked after
/// every step (the engine's own complaint, a non-finite state, a speed beyond
/// the blow-up bound: each at the step's time, not the next sample's),
/// evaluations as the engine counts them, and the dampers' work W_diss
/// integrated by the harness to fourth order (docs/report-format.md).
#include <limits>
#include <string>
#include <vector>

#include "solver/trajectory.hpp"

namespace em {

/// A fixed-step engine's model of one scene, at its current state.
class FixedStepEngine {
 public:
  virtual ~FixedStepEngine() = default;
  /// One step of exactly the run's dt; "" or the engine's complaint, one line, naming it ("MuJoCo: ...").
  virtual std::string step() = 0;
  /// A joint controller's generalized forces (theory.md §18), one per in-house
  /// speed (internal order; 0 off the controlled joints), applied on top of
  /// everything else and held over its steps until the next call.  // tau: (nu)
  virtual void applyControl(const Eigen::VectorXd& tau) = 0;
  /// Evaluations of its equations so far (steps' stages, not the harness's own reads).
  virtual long evaluations() const = 0;
  /// The current state as in-house (q, u), internal order.  // q: (nq), u: (nu)
  virtual void state(Eigen::VectorXd& q, Eigen::VectorXd& u) = 0;
  /// The current state's body poses (internal order) and energies; called
  /// before state() at every sample.
  virtual void sample(std::vector<Pose>& poses, double& kinetic, double& potential) = 0;
  /// The dampers' power P = sum c u^2 at the current state and its rate
  /// P' = 2 sum c u u' (the model has dampers only).
  virtual void dissipation(double& P, double& Pdot) = 0;
  /// The largest distance (m) between a joint's two points at the state
  /// state() last read: a maximal-coordinate engine's constraint violation
  /// (ODE); NaN where the joints hold by construction.
  virtual double jointSeparation() const { return std::numeric_limits<double>::quiet_NaN(); }
};

/// Integrate `engine` from its initial state on the grid of `spec` (fixed
/// step spec.dt). A joint controller is sampled from the engine's state at
/// the starts of the steps on its instants (every step for a continuous one:
/// an engine holds it over its step) and its work, exact under the hold
/// (tau . dq), is counted negative in W_diss. A failure ends the run with its time and cause; CPU time
/// counts the steps alone, the harness's reads and W_diss apart.
Trajectory runFixedStep(const Model& m, const CheckedRunSpec& run, FixedStepEngine& engine, const SampleObserver& observe);

/// An engine row's `simulate` for a FixedStepEngine made as Stepper(m, spec):
/// the one loop.
template <class Stepper>
Trajectory simulateFixedStep(const Model& m, const CheckedRunSpec& run, const SampleObserver& observe) {
  Stepper stepper(m, run.spec());
  return runFixedStep(m, run, stepper, observe);
}

/// W_diss over one step of h from (P0, P0') to (P1, P1'): the trapezoid rule
/// with its end corrections, h/2 (P0 + P1) + h^2/12 (P0' - P1'), exact for
/// cubics (error h^5/720 P''''): fourth order, as rk4.
inline double dissipatedOverStep(double h, double P0, double Pdot0, double P1, double Pdot1) {
  return 0.5 * h * (P0 + P1) + h * h / 12.0 * (Pdot0 - Pdot1);
}

}  // namespace em
