#pragma once
// Shared helpers of the tests: data paths, run settings, relative errors, random states.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "io/json_input.hpp"
#include "io/scene.hpp"
#include "io/scene_json.hpp"
#include "solver/model.hpp"
#include "solver/run_spec.hpp"
#include "solver/trajectory.hpp"

namespace em::test {

inline std::string sourcePath(const std::string& rel) { return std::string(EM_SOURCE_DIR) + "/" + rel; }
inline Scene sceneData(const std::string& scene) { return loadScene(sourcePath("data/scenes/" + scene)); }
inline Model loadData(const std::string& scene) { return sceneData(scene).model; }
/// data/scenes/<scene> as written, for tests that alter it before building.
inline SceneSpec loadSpec(const std::string& scene) { return parseSceneSpec(readFile(sourcePath("data/scenes/" + scene), "scene")); }

/// Whether a temporary of an atomic write of `path` (`<path>.tmp.<pid>`) is left beside it.
inline bool temporaryLeft(const std::string& path) {
  const std::filesystem::path p(path);
  const std::string prefix = p.filename().string() + ".tmp";
  for (const auto& f : std::filesystem::directory_iterator(p.parent_path()))
    if (f.path().filename().string().rfind(prefix, 0) == 0) return true;
  return false;
}

/// The n-link chain as data/scenes/chainNN.json defines it (tools/make_scenes.py),
/// as written, for tests that alter it before building.
inline SceneSpec chainSpec(int n) {
  char name[32];
  std::snprintf(name, sizeof name, "data/scenes/chain%02d.json", n);
  return parseSceneSpec(readFile(sourcePath(name), "scene"));
}

/// chain01 with its CM at the joint point (A = P^T J P: rank 2 when the
/// gimbal's middle angle is +-90 deg) at middle angle q1.
inline Model lockedGimbal(double q1) {
  SceneSpec s = chainSpec(1);
  s.bodies[0].joint.in_body = Vec3::Zero();
  s.bodies[0].joint.q0 = Vec3(0.3, q1, 0.2);
  return buildModel(s);
}

/// A run of `method` with `integrator` at dt (fixed step) or tol (adaptive)
/// `setting`, sampled every output_dt up to t_end.
/// One body on a ball joint at the ground (quaternion q0, body-frame angular velocity u0),
/// its joint point at `in_body` from its CM: the spinning tops and spheres of the tests.
inline Model bodyOnBall(const std::string& name, double mass, const Mat3& inertia, const Vec3& in_body,
                        const Eigen::Vector4d& q0, const Vec3& u0, const Vec3& gravity) {
  SceneSpec s;
  s.name = name;
  s.gravity = gravity;
  BodySpec b;
  b.name = name;
  b.parent = "ground";
  b.mass = mass;
  b.inertia = inertia;
  b.joint.type = JointType::Ball;
  b.joint.in_body = in_body;
  b.joint.q0 = q0;
  b.joint.u0 = u0;
  s.bodies.push_back(b);
  return buildModel(s);
}

inline RunSpec runSpec(Method method, Integrator integrator, double t_end, double setting, double output_dt = 0.01) {
  RunSpec s;
  s.method = method;
  s.integrator = integrator;
  s.setSetting(setting);
  s.t_end = t_end;
  s.output_dt = output_dt;
  return s;
}

/// A random tree of `n` bodies: random parents, axes, masses, inertias,
/// levers, springs on every other body, initial state; a scene no method was
/// tuned on. Joints: revolute, universal, gimbal, prismatic; with `all_kinds`
/// also ball and free (then with turned, full inertia matrices too); with
/// `revolute_only`, every joint revolute (the same draws otherwise).
inline Model randomTree(unsigned seed, int n, bool all_kinds = false, bool revolute_only = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1, 1), pos(0.2, 1.0);
  auto unit = [&] { return Vec3(uni(rng), uni(rng), uni(rng)).normalized(); };
  SceneSpec s;
  s.name = "random" + std::to_string(seed);
  // Without all_kinds: the first four (no quaternion); with it: every row of the table.
  const JointType kinds[] = {JointType::Revolute, JointType::Universal, JointType::Gimbal,
                             JointType::Prismatic, JointType::Ball,      JointType::Free, JointType::Planar};
  static_assert(std::size(kinds) == std::size(kJointTypes), "randomTree draws every joint kind");
  for (int i = 0; i < n; ++i) {
    BodySpec b;
    b.name = "b" + std::to_string(i);
    b.parent = i == 0 ? "ground" : "b" + std::to_string(std::uniform_int_distribution<int>(0, i - 1)(rng));
    b.mass = pos(rng);
    const Vec3 I(pos(rng), pos(rng), pos(rng));
    b.inertia = (0.1 * (I + Vec3::Constant(I.sum()))).asDiagonal();  // within the triangle inequality
    b.joint.type = kinds[std::uniform_int_distribution<int>(0, all_kinds ? int(std::size(kinds)) - 1 : 3)(rng)];
    if (revolute_only) b.joint.type = JointType::Revolute;
    b.joint.axis[0] = unit();
    b.joint.axis[1] = b.joint.axis[0].unitOrthogonal();
    b.joint.in_parent = 0.4 * Vec3(uni(rng), uni(rng), uni(rng));
    b.joint.in_body = 0.4 * Vec3(uni(rng), uni(rng), uni(rng));
    const int nq = jointNq(b.joint.type), nu = jointNu(b.joint.type), at = jointQuat(b.joint.type);
    b.joint.q0 = 0.5 * Eigen::VectorXd::NullaryExpr(nq, [&] { return uni(rng); });
    b.joint.u0 = Eigen::VectorXd::NullaryExpr(nu, [&] { return uni(rng); });
    if (at >= 0) b.joint.q0.segment<4>(at).normalize();
    if (all_kinds || revolute_only) {  // full inertia tensors, turned off the joint axes (a diagonal-only export must show)
      const Mat3 R = Eigen::Quaterniond(Eigen::Vector4d(uni(rng), uni(rng), uni(rng), uni(rng)).normalized()).toRotationMatrix();
      b.inertia = R * b.inertia * R.transpose();
    }
    if (i % 2 == 1 && at < 0) {
      b.joint.has_spring = true;
      b.joint.spring = {Eigen::VectorXd::Constant(nq, 3.0), Eigen::VectorXd::Constant(nq, 0.1), Eigen::VectorXd::Zero(nq)};
    }
    s.bodies.push_back(b);
  }
  return buildModel(s);
}

/// Every scene of data/scenes/ (kept in step with the folder by a test).
inline const std::vector<std::string>& dataScenes() {
  static const std::vector<std::string> s = {
      "cartpole.json", "chain01.json", "chain02.json", "chain03.json", "chain04.json", "chain05.json", "chain06.json",
      "chain07.json", "chain08.json", "chain09.json", "chain10.json", "chain20.json", "chain50.json", "floating_arm.json", "forest.json", "pendulum5.json",
      "pendulum5_ball.json", "planar_sled.json", "solo12_tumbling.json", "spring_damper.json", "tree_mixed.json"};
  return s;
}

/// max|a - b| / max(max|b|, floor): relative to the reference's own magnitude.
template <class X, class Y>
double relErr(const X& a, const Y& b, double floor = 0.0) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), floor);
}

/// Round-off bound of u' = A^-1 B relative to max|u'|: a backward-stable solve
/// errs by ~eps cond(A) (measured: at most 0.45 eps cond(A) on every data
/// scene), so the bound is max(floor, 4 eps cond(A)); cond(A) reaches 2e6 on chain50.
inline double udotTolerance(const Eigen::MatrixXd& A, double floor = 1e-12) {
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A, Eigen::EigenvaluesOnly).eigenvalues();
  return std::max(floor, 4 * 2.220446049250313e-16 * ev.maxCoeff() / ev.minCoeff());
}

/// Largest |q - q'| and |u - u'| over the samples of two runs up to t_max.
inline double stateDiff(const Trajectory& a, const Trajectory& b, double t_max) {
  double d = 0;
  for (size_t k = 0; k < std::min(a.size(), b.size()) && a.t[k] <= t_max + 1e-12; ++k)
    d = std::max({d, (a.q[k] - b.q[k]).cwiseAbs().maxCoeff(), (a.u[k] - b.u[k]).cwiseAbs().maxCoeff()});
  return d;
}

/// Largest CM distance (m) or rotation angle (rad) between two runs' body poses, over their common samples.
inline double maxPoseDiff(const Trajectory& a, const Trajectory& b) {
  double d = 0;
  for (size_t k = 0; k < std::min(a.size(), b.size()); ++k)
    for (size_t i = 0; i < a.poses[k].size(); ++i) {
      d = std::max(d, (a.poses[k][i].p - b.poses[k][i].p).norm());
      d = std::max(d, rotationAngleBetween(quatToMatrix(a.poses[k][i].quat), quatToMatrix(b.poses[k][i].quat)));
    }
  return d;
}

/// Models of every joint kind: the shipped scenes that hold them (gimbal,
/// ball, universal, slides, a free base, springs and dampers) and random
/// trees of all six kinds with turned full inertias (free joints inside).
inline std::vector<Model> modelsOfEveryKind() {
  std::vector<Model> models;
  for (const char* s : {"pendulum5.json", "pendulum5_ball.json", "floating_arm.json", "tree_mixed.json", "spring_damper.json",
                        "planar_sled.json"})
    models.push_back(loadData(s));
  for (unsigned seed : {1u, 2u, 3u, 4u}) models.push_back(randomTree(seed, 6, true));
  return models;
}

/// A free top in zero gravity: a full inertia, its joint point off the CM,
/// turning about all three axes (Erez et al.'s momentum test).
inline Model freeTop() {
  SceneSpec s;
  s.name = "free_top";
  s.gravity = Vec3::Zero();
  BodySpec b;
  b.name = "top";
  b.parent = "ground";
  b.mass = 3.0;
  b.inertia = Vec3(0.3, 0.5, 0.65).asDiagonal();
  b.inertia(0, 1) = b.inertia(1, 0) = 0.04;
  b.joint.type = JointType::Free;
  b.joint.in_parent = Vec3(0.1, 0.2, 0.3);
  b.joint.in_body = Vec3(0.2, -0.1, 0.3);
  b.joint.q0.resize(7);
  b.joint.q0 << 0.1, -0.2, 0.3, 0.9, 0.1, -0.3, 0.2;
  b.joint.q0.tail<4>().normalize();
  b.joint.u0.resize(6);
  b.joint.u0 << 0.3, -0.5, 0.2, 1.5, -2.0, 0.7;
  s.bodies.push_back(b);
  return buildModel(s);
}

/// A random state (solver/model.hpp): angles in [-pi, pi], unit quaternions, speeds in [-2, 2] rad/s.
using em::randomState;

}  // namespace em::test
