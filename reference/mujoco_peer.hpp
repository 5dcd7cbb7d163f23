#pragma once
/// MuJoCo as a benchmark peer: the same scene as MJCF (body frames at the
/// CMs, parallel to the parent's at zero coordinates as in the scene; a
/// revolute joint is one hinge, a universal two, a gimbal three hinges x, y, z
/// in one body, applied in order about the turned axes, as Rx Ry Rz; inertia
/// as diaginertia or fullinertia; contacts, constraints and passive forces off).
/// Ball joints are not mapped (MuJoCo's ball speed is in the child's frame).
/// Built only when CMake finds MuJoCo (EM_HAVE_MUJOCO).
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "solver/model.hpp"

namespace em {

/// The MJCF of `m` as (file name, text): "scene.xml" first, then the files it
/// includes (MuJoCo's parser allows 100 nested elements per file).
std::vector<std::pair<std::string, std::string>> toMjcf(const Model& m);

class MujocoPeer {
 public:
  /// Throws std::runtime_error with MuJoCo's message if the model does not compile.
  explicit MujocoPeer(const Model& m);
  ~MujocoPeer();
  MujocoPeer(const MujocoPeer&) = delete;
  MujocoPeer& operator=(const MujocoPeer&) = delete;
  /// qpos, qvel from in-house q, u (internal order).  // q: (nq), u: (nu)
  void setState(const Eigen::VectorXd& q, const Eigen::VectorXd& u);
  /// mj_forward: everything up to the accelerations.
  void forward();
  /// After forward(): the mass matrix and B = -qfrc_bias, in-house order.  // (nu x nu), (nu)
  Eigen::MatrixXd massMatrix() const;
  Eigen::VectorXd rhs() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace em
