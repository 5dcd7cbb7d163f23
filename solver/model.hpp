#pragma once
/// The immutable model of a tree of rigid bodies: topology (regular numbering,
/// structure matrix T), bodies, joints and the map back to the scene file's order.
/// docs/theory.md §1–2.
#include <stdexcept>
#include <string>
#include <vector>

#include "solver/rotation.hpp"

namespace em {

enum class JointType { Revolute, Universal, Gimbal, Ball };

const char* jointTypeName(JointType t);
/// Number of generalized coordinates of a joint kind (ball: 4, a quaternion).
int jointNq(JointType t);
/// Number of generalized speeds of a joint kind.
int jointNu(JointType t);

/// A scene error: carries the JSON path of the offending key and what is wrong.
struct SceneError : std::runtime_error {
  SceneError(const std::string& path, const std::string& what)
      : std::runtime_error(path + ": " + what), path(path) {}
  std::string path;
};

/// Per-coordinate linear spring-damper, generalized force -k (q - q_rest) - c u.
struct Spring {
  Eigen::VectorXd k, c, q_rest;  // (nu) each
};

/// One joint: the inboard joint of its body.
struct Joint {
  JointType type = JointType::Revolute;
  Vec3 axis[2] = {Vec3::UnitX(), Vec3::UnitY()};  ///< unit axes (revolute: [0]; universal: both)
  Vec3 in_parent = Vec3::Zero();  ///< a: parent CM -> joint point, parent frame (world for roots)
  Vec3 in_body = Vec3::Zero();    ///< c: body CM -> joint point, body frame
  Eigen::VectorXd q0, u0;         ///< initial coordinates (nq) and speeds (nu)
  bool has_spring = false;
  Spring spring;
};

/// A body as written in a scene: parent by name, file order.
struct BodySpec {
  std::string name, parent;  ///< parent "ground" or another body's name
  double mass = 1.0;
  Mat3 inertia = Mat3::Identity();  ///< about the CM, body frame (matrix entries)
  Joint joint;
};

/// A scene as written: bodies in file order.
struct SceneSpec {
  std::string name;
  Vec3 gravity{0, 0, -9.81};
  std::vector<BodySpec> bodies;
  double t_end = 10.0, output_dt = 0.01;
};

/// A body of the model, in regular (parents-first) numbering.
struct Body {
  std::string name;
  int parent = -1;        ///< internal index of the parent, -1 for the ground
  double mass = 0;
  Mat3 J;                 ///< inertia about the CM, body frame  (3x3)
  Joint joint;
  int iq = 0, iu = 0;     ///< offsets of this joint's q and u in the internal state
  int file_index = 0;     ///< index in the scene file's body list
  int file_iq = 0, file_iu = 0;  ///< offsets in the file-order q and u
  std::vector<int> children;
  int nq() const { return jointNq(joint.type); }
  int nu() const { return jointNu(joint.type); }
};

/// Immutable model built once from a scene (Pinocchio's Model, MuJoCo's mjModel).
struct Model {
  std::string name;
  Vec3 gravity = Vec3::Zero();
  std::vector<Body> bodies;    ///< regular numbering: parent(i) < i
  int nq = 0, nu = 0;
  bool has_springs = false;    ///< build the joint-force term Q only when declared
  bool has_gravity = false;
  Eigen::MatrixXi T;           ///< structure matrix: T(j,i) = 1 if j is i or an ancestor of i  (n x n)
  std::vector<int> file_to_internal;  ///< body index map
  double t_end = 10.0, output_dt = 0.01;

  int n() const { return static_cast<int>(bodies.size()); }
  /// Initial state in internal order: q (nq), u (nu).
  Eigen::VectorXd q0() const;
  Eigen::VectorXd u0() const;
  /// Permute a file-order q (or u) into internal order and back.
  void qFromFile(const Eigen::VectorXd& qf, Eigen::VectorXd& q) const;
  void qToFile(const Eigen::VectorXd& q, Eigen::VectorXd& qf) const;
  void uFromFile(const Eigen::VectorXd& uf, Eigen::VectorXd& u) const;
  void uToFile(const Eigen::VectorXd& u, Eigen::VectorXd& uf) const;
  /// Permutation p with (file-order u)[k] = (internal u)[p[k]].
  std::vector<int> uFilePermutation() const;
  /// Names of coordinates and speeds in file order ("link1.q0", "link1.u0").
  std::vector<std::string> qNames() const;
  std::vector<std::string> uNames() const;
};

/// Validate the topology and renumber parents-first. Throws SceneError naming
/// `bodies[i].parent` / `bodies[i].name` (file indices) on duplicate names,
/// unknown parents or cycles.
Model buildModel(const SceneSpec& spec);

/// A chain of n identical slender links (the paper's n-link pendulum family):
/// a gimbal at the top, then revolute joints alternating about x and y.
SceneSpec makeChainSpec(int n, bool ball_root = false);

}  // namespace em
