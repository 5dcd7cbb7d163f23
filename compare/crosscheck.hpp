#pragma once
/// The in-house equations against independent engines at many states: A, B
/// and u' at the initial state and at random ones, against Simbody (the same
/// Model as a Simbody system) and MuJoCo (for a URDF, MuJoCo's own reading of
/// the file; for a JSON scene, the Model as MJCF, ball joints excepted).
#include <string>
#include <vector>

#include "io/scene.hpp"

namespace em {

/// Largest differences at one state, relative to the in-house value's largest
/// entry: max|X_engine - X_inhouse| / max|X_inhouse| for A, B and u'.
struct CrossCheckRow {
  int state = 0;  ///< 0: the initial state; k > 0: the k-th random one
  std::string engine;
  double A = 0, B = 0, udot = 0;
  double worst() const { return std::max(A, std::max(B, udot)); }
};

/// max|x - y| / max|y| (1 in place of a zero max|y|): how far x is from y, relative to y's largest entry.
double relativeDifference(const Eigen::MatrixXd& x, const Eigen::MatrixXd& y);

/// The engine name of the rows that hand the in-house formation MuJoCo's
/// compiled masses, CMs and inertias: what differs there is not inertia.
constexpr const char* kMujocoMass = "mujoco-mass";

struct CrossCheck {
  std::vector<CrossCheckRow> rows;
  std::vector<std::string> skipped;  ///< engines that cannot take this scene, and why
};

/// `states` random states after the initial one (randomState, seeded `seed`).
/// For a URDF scene, `urdf` must be the options it was loaded with.
CrossCheck crossCheck(const Scene& scene, const UrdfOptions& urdf, int states, unsigned seed);

}  // namespace em
