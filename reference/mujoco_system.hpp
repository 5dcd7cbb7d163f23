#pragma once
/// MuJoCo (libmujoco-dev) as an independent engine: a benchmark peer for
/// scenes and the second reader of URDF robots.
///
/// From a Model: the same scene as MJCF (body frames at the
/// CMs, parallel to the parent's at zero coordinates as in the scene; a
/// revolute joint is one hinge, a universal two, a gimbal three hinges x, y, z
/// in one body, applied in order about the turned axes, as Rx Ry Rz; inertia
/// as diaginertia or fullinertia; joint springs and dampers as stiffness,
/// springref and damping; contacts and constraints off).
/// A prismatic joint is a slide; a ball MuJoCo's ball, a free joint three
/// slides and a ball (MuJoCo's free joint must hang from the world): MuJoCo
/// reads their angular speed in the child's frame, which setState and the
/// getters turn to and from the parent's.
///
/// From a URDF: MuJoCo compiles the file itself (its own URDF reader, its own
/// fixed-joint fusion and frame arithmetic), with visual and collision
/// elements removed (meshes need not exist), locked joints made fixed, and
/// contacts, constraints (joint limits) and passive forces (URDF damping and
/// friction) off, since the scene has none of them.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "reference/engine.hpp"
#include "solver/model.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// The closure kinds MuJoCo's connect equalities express (mjConnects): the
/// others are refused by name (mujoco.cpp's mechanismRefusal).
inline const std::vector<LoopType> kMjLoops = {LoopType::Ball, LoopType::Hinge, LoopType::Weld};

/// The MJCF of `m` as (file name, text): "scene.xml" first, then the files it
/// includes (MuJoCo's parser allows 100 nested elements per file).
std::vector<std::pair<std::string, std::string>> toMjcf(const Model& m);

class MujocoSystem {
 public:
  /// Throws std::runtime_error with MuJoCo's message if the model does not compile.
  explicit MujocoSystem(const Model& m);
  /// MuJoCo's reading of `urdf_text`; `joints` names the URDF joint of each
  /// body of `m` in source (file) order (Scene::source_joints). `locked`
  /// joints become fixed; `balance_inertia` sets MuJoCo's balanceinertia;
  /// a `floating_joint` name frees the root link by a URDF floating joint
  /// of that name, which MuJoCo reads as its free joint.
  MujocoSystem(const Model& m, const std::string& urdf_text, const std::vector<std::string>& joints,
             const std::vector<std::string>& locked, bool balance_inertia, const std::string& floating_joint = "");
  ~MujocoSystem();
  MujocoSystem(const MujocoSystem&) = delete;
  MujocoSystem& operator=(const MujocoSystem&) = delete;
  /// qpos, qvel from in-house q, u (internal order).  // q: (nq), u: (nu)
  void setState(const Eigen::VectorXd& q, const Eigen::VectorXd& u);
  /// mj_forward: everything up to the accelerations.
  void forward();
  /// After forward(): the mass matrix, B = -qfrc_bias and u' = qacc, in-house order.  // (nu x nu), (nu), (nu)
  Eigen::MatrixXd massMatrix() const;
  Eigen::VectorXd rhs() const;
  Eigen::VectorXd acceleration() const;
  /// The same u' written into `udot` (nu), allocating nothing.
  void acceleration(double* udot) const;
  /// MuJoCo's compiled mass properties of each in-house body (internal order),
  /// at the zero configuration (leaves the state at zero).
  std::vector<CompiledMass> compiledMass();

  // Stepping (reference/mujoco.cpp): the peer as a trajectory engine.
  /// Fixed step dt with MuJoCo's integrator `scheme` (mjINT_EULER, mjINT_RK4,
  /// mjINT_IMPLICIT); with `energies`, every forward computes them (mjENBL_ENERGY).
  void configure(int scheme, double dt, bool energies = true);
  /// Whether forward computes the energies (mjENBL_ENERGY), the state kept: on for a
  /// sample, off for the timed steps (issue 75, item 6: on, they cost ~4 % inside the timer).
  void computeEnergies(bool on);
  /// One mj_step (after setState and forward).
  void step();
  /// Every closure's softness (its connect equalities): solref (time constant
  /// s, damping ratio) and solimp's first three (d0, d_width, width m); MuJoCo's
  /// own defaults are 0.02 1 and 0.9 0.95 0.001.
  void soften(const double solref[2], const double solimp[3]);
  /// Every limited joint's solreflimit (time constant, damping ratio).
  void softenLimits(const double solref[2]);
  /// qfrc_applied = the drives + tau, a generalized force per in-house speed
  /// (internal order) on joints whose speeds MuJoCo reads as ours (a joint
  /// controller's: theory.md §18), held until the next call.  // tau: (nu)
  void applyControl(const Eigen::VectorXd& tau);
  /// In-house q, u (internal order) from qpos, qvel.  // q: (nq), u: (nu)
  void getState(Eigen::VectorXd& q, Eigen::VectorXd& u) const;
  /// Body poses (CM position, orientation), internal order, as of the last forward.
  std::vector<Pose> poses() const;
  /// Kinetic and potential energy (gravity, springs) as of the last forward.
  double kineticEnergy() const;
  double potentialEnergy() const;
  /// The dampers' power sum of c u^2 at the current speeds.
  double dissipationRate() const;
  /// Its rate 2 sum c u u' (after forward: qacc of the current state).
  double dissipationRateDerivative() const;
  /// MuJoCo's warnings raised so far ("" if none), one line.
  std::string warnings() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace em
