// Joint-space control (docs/theory.md §18).
#include "solver/control.hpp"

#include <algorithm>

#include "solver/text.hpp"

namespace em {

void tableAt(const std::vector<double>& times, const Eigen::MatrixXd& rows, double t, double* x, double* dx) {
  const int cols = static_cast<int>(rows.cols()), last = static_cast<int>(times.size()) - 1;
  const auto hold = [&](int i) {
    for (int c = 0; c < cols; ++c) {
      x[c] = rows(i, c);
      if (dx) dx[c] = 0;
    }
  };
  if (t <= times.front()) return hold(0);
  if (t >= times.back()) return hold(last);
  // The segment [t_i, t_i+1) holding t (times strictly increasing: io checks).
  const int i = static_cast<int>(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  const double h = times[i + 1] - times[i], s = (t - times[i]) / h;
  for (int c = 0; c < cols; ++c) {
    x[c] = rows(i, c) + s * (rows(i + 1, c) - rows(i, c));
    if (dx) dx[c] = (rows(i + 1, c) - rows(i, c)) / h;
  }
}

void targetAt(const ControlTarget& target, double t, double* q, double* qdot) {
  switch (target.type) {
    case TargetType::Constant:
      for (int k = 0; k < target.q.size(); ++k) q[k] = target.q[k], qdot[k] = 0;
      return;
    case TargetType::Sine:
      for (int k = 0; k < target.offset.size(); ++k) {
        const double w = 2 * M_PI * target.frequency_hz[k];
        q[k] = target.offset[k] + target.amplitude[k] * std::sin(w * t);
        qdot[k] = target.amplitude[k] * w * std::cos(w * t);
      }
      return;
    case TargetType::Table:
      tableAt(target.t, target.rows, t, q, qdot);
      return;
  }
}

void controlTorques(const Model& m, double t, const double* q, const double* u, Eigen::VectorXd& tau) {
  tau.setZero();
  constexpr int kMaxNu = 6;
  double qs[kMaxNu], qsdot[kMaxNu];
  for (const Body& b : m.bodies) {
    if (!b.joint.control) continue;
    const JointControl& c = *b.joint.control;
    if (c.type == ControlType::TorqueTable) {
      tableAt(c.t, c.tau, t, tau.data() + b.iu, nullptr);
      continue;
    }
    targetAt(c.target, t, qs, qsdot);
    for (int k = 0; k < b.nu(); ++k) {
      const double f = c.kp[k] * (qs[k] - q[b.iq + k]) + c.kd[k] * (qsdot[k] - u[b.iu + k]);
      tau[b.iu + k] = std::clamp(f, -c.effort[k], c.effort[k]);
    }
  }
}

double controlWork(const Model& m, const Eigen::VectorXd& tau, const Eigen::VectorXd& q0, const Eigen::VectorXd& q1) {
  double W = 0;
  for (const Body& b : m.bodies)
    if (b.joint.control)
      for (int k = 0; k < b.nu(); ++k) W += tau[b.iu + k] * (q1[b.iq + k] - q0[b.iq + k]);
  return W;
}

std::string controlStepRefusal(const Model& m, double dt) {
  if (!m.has_control || !(m.control_period > 0) || stepsPerControlPeriod(m.control_period, dt)) return "";
  return "option --dt: " + gnum(dt) + " s does not divide the control period " + gnum(m.control_period) +
         " s (a fixed-step run samples its controller at step starts)";
}

long stepsPerControlPeriod(double period, double dt) {
  const double r = period / dt;
  const long n = std::lround(r);
  return n >= 1 && std::abs(r - static_cast<double>(n)) <= 1e-9 * r ? n : 0;
}

}  // namespace em
