#pragma once
// Synthetic trajectories with known errors: one body turning about z on a unit
// circle; the run's angle error is `slope * t`, its energy grows by `drift * t`.
#include "solver/trajectory.hpp"

namespace em::test {

/// `method` runs on its engine's default integrator (in-house rk4 at dt 1e-3).
inline Trajectory turning(Method method, double slope, double drift, double t_end = 10.0, double dt = 0.01) {
  Trajectory tr;
  tr.run.method = method;
  tr.run.integrator = defaultIntegrator(info(method).engine);
  tr.run.t_end = t_end;
  tr.run.output_dt = dt;
  tr.q_names = {"body.q0"};
  tr.angle_coords = {0};
  tr.u_names = {"body.u0"};
  tr.body_names = {"body"};
  const int n = static_cast<int>(std::lround(t_end / dt));
  for (int k = 0; k <= n; ++k) {
    const double t = k * dt, th = 0.3 * t + slope * t;
    tr.t.push_back(t);
    tr.q.push_back(Eigen::VectorXd::Constant(1, th));
    tr.u.push_back(Eigen::VectorXd::Constant(1, 0.3 + slope));
    tr.energy.push_back(-5.0 + drift * t);
    tr.kinetic.push_back(2.0);
    tr.dissipated.push_back(0.0);
    tr.poses.push_back({Pose{Vec3(std::cos(th), std::sin(th), 0), Vec4(std::cos(th / 2), 0, 0, std::sin(th / 2))}});
  }
  return tr;
}

}  // namespace em::test
