#pragma once
// Shared helpers of the tests: data paths, run settings, relative errors, random states.
#include <cmath>
#include <cstdio>
#include <filesystem>
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

/// A run of `method` with `integrator` at dt (fixed step) or tol (adaptive)
/// `setting`, sampled every output_dt up to t_end.
inline RunSpec runSpec(Method method, Integrator integrator, double t_end, double setting, double output_dt = 0.01) {
  RunSpec s;
  s.method = method;
  s.integrator = integrator;
  (s.fixedStep() ? s.dt : s.tol) = setting;
  s.t_end = t_end;
  s.output_dt = output_dt;
  return s;
}

/// Every scene of data/scenes/ (kept in step with the folder by a test).
inline const std::vector<std::string>& dataScenes() {
  static const std::vector<std::string> s = {
      "cartpole.json", "chain01.json", "chain02.json", "chain03.json", "chain04.json", "chain05.json", "chain06.json",
      "chain07.json", "chain08.json", "chain09.json", "chain10.json", "chain20.json", "chain50.json", "floating_arm.json", "forest.json", "pendulum5.json",
      "pendulum5_ball.json", "spring_damper.json", "tree_mixed.json"};
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

/// A random state (solver/model.hpp): angles in [-pi, pi], unit quaternions, speeds in [-2, 2] rad/s.
using em::randomState;

}  // namespace em::test
