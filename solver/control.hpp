#pragma once
/// Joint-space control (docs/theory.md §18): each controlled joint's torque
/// from its target and the state, one function per piece, and the loop that
/// evaluates it continuously or samples it every period and holds it
/// (zero-order hold). The torques enter B as generalized forces (eq. (C1))
/// and their power counts negative in W_diss, as a drive's (eq. (C3)).
#include <cmath>
#include <limits>
#include <string>

#include "solver/model.hpp"

namespace em {

/// Linear interpolation of a table's rows at time t, held beyond its ends:
/// the row into x, and the slope (0 beyond the ends) into dx (may be null).  // x, dx: (cols)
void tableAt(const std::vector<double>& times, const Eigen::MatrixXd& rows, double t, double* x, double* dx);
/// The target q*(t) and its rate q*'(t) of one joint's controller (eq. (C2)).  // q, qdot: (nu)
void targetAt(const ControlTarget& target, double t, double* q, double* qdot);
/// Every controlled joint's generalized torque at (t, q, u), internal order,
/// into tau (eq. (C1)); uncontrolled speeds get 0.  // q: (nq), u, tau: (nu)
void controlTorques(const Model& m, double t, const double* q, const double* u, Eigen::VectorXd& tau);

/// The controller as a run evaluates it: continuous (every right-hand side),
/// or sampled at t_k = k period and held until the next sample.
class ControlLoop {
 public:
  explicit ControlLoop(const Model& m) : m_(m), held_(m.has_control ? m.nu : 0) { held_.setZero(); }
  bool active() const { return m_.has_control; }
  bool sampled() const { return m_.control_period > 0; }
  double period() const { return m_.control_period; }
  /// The torques at (t, q, u) into tau: computed (continuous) or the held ones (sampled).  // tau: (nu)
  void torques(double t, const double* q, const double* u, Eigen::VectorXd& tau) const {
    if (sampled()) tau = held_;
    else controlTorques(m_, t, q, u, tau);
  }
  /// A sample at t_k: compute and hold the torques there.
  void sample(double t, const double* q, const double* u) { controlTorques(m_, t, q, u, held_); }
  const Eigen::VectorXd& held() const { return held_; }
  /// The sampling instant after t (t itself excluded), +inf for a continuous loop.
  double nextSample(double t) const {
    if (!sampled()) return std::numeric_limits<double>::infinity();
    const double k = std::floor(t / period() + 1e-9) + 1;
    return k * period();
  }

 private:
  const Model& m_;
  Eigen::VectorXd held_;  // (nu)
};

/// The work of torques tau held over a step from q0 to q1 (internal order):
/// sum over the controlled joints' coordinates of tau (q1 - q0), exact under
/// a zero-order hold (their q' = u).  // tau: (nu), q0, q1: (nq)
double controlWork(const Model& m, const Eigen::VectorXd& tau, const Eigen::VectorXd& q0, const Eigen::VectorXd& q1);

/// The steps of dt in one control period, or 0 where the period is not a
/// whole number of steps (to 1e-9 of it): a fixed-step run samples its
/// controller at step starts.
long stepsPerControlPeriod(double period, double dt);
/// Why a fixed-step run of dt cannot sample `m`'s controller ("option --dt:
/// ... does not divide the control period ..."), or "": the one rule, which
/// the in-house integrators, the engines' refusal and their loop all read.
std::string controlStepRefusal(const Model& m, double dt);

}  // namespace em
