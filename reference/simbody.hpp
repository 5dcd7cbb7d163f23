#pragma once
/// A Simbody model of the very same scene (built from the loaded em::Model,
/// not a second parser): the harness's independent reference.
/// Simbody types stay behind a pimpl so no other folder includes its headers.
#include <memory>
#include <string>
#include <vector>

#include "solver/model.hpp"
#include "solver/trajectory.hpp"

namespace em {

class SimbodySystem {
 public:
  explicit SimbodySystem(const Model& m);
  ~SimbodySystem();
  SimbodySystem(const SimbodySystem&) = delete;
  SimbodySystem& operator=(const SimbodySystem&) = delete;

  /// Set the state from in-house (q, u), internal order.  // q: (nq), u: (nu)
  void setState(const Eigen::VectorXd& q, const Eigen::VectorXd& u);
  /// Read Simbody's state back as in-house (q, u), internal order.
  void getState(Eigen::VectorXd& q, Eigen::VectorXd& u) const;
  /// Mass matrix from calcM, in-house internal order.  // (nu x nu)
  Eigen::MatrixXd massMatrix();
  /// B = -(residual of calcResidualForceIgnoringConstraints at u' = 0).  // (nu)
  Eigen::VectorXd rhs();
  /// u' from realize(Acceleration).  // (nu)
  Eigen::VectorXd udot();
  double kineticEnergy();
  double potentialEnergy();
  /// Body poses (CM position, orientation quaternion), internal order.
  std::vector<Pose> poses();

  /// Integrate from the model's initial state as `spec` says: method simbody,
  /// a Simbody integrator (rkmerson, rk3, cpodes) at accuracy spec.tol,
  /// sampled every spec.output_dt. A numerical failure ends the run with its
  /// time and cause in the trajectory; bad settings throw.
  Trajectory simulate(const CheckedRunSpec& spec, const SampleObserver& observe = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace em
