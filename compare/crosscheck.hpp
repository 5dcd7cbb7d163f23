#pragma once
/// The in-house equations against independent engines at many states: A, B
/// and u' at the initial state and at random ones, against every engine whose
/// row gives equations at a state (reference/engine.hpp): for a URDF, the
/// engine's own reading of the file where it has one (MuJoCo), else the Model.
#include <map>
#include <random>
#include <string>
#include <vector>

#include "reference/engine.hpp"
#include "io/scene.hpp"
#include "solver/registry.hpp"

namespace em {

/// Largest differences at one state, relative to the in-house value's largest
/// entry: max|X_engine - X_inhouse| / max|X_inhouse| for A, B and u' (on a
/// mechanism: the constrained u', relative to the larger of its largest entry
/// and the free u' = A^-1 B's, at states projected onto the loops).
struct CrossCheckRow {
  int state = 0;  ///< 0: the initial state; k > 0: the k-th random one
  std::string engine;
  double A = 0, B = 0, udot = 0;
  bool udot_only = false;  ///< a plugin's row: it gives u' alone (A and B are 0)
  bool A_only = false;     ///< an engine whose equations at a state are a mechanism's tree (EngineCode::mechanism_state): A alone (B and u' are 0)
  double worst() const { return std::max(A, std::max(B, udot)); }
};

/// max|x - y| / max|y| (1 in place of a zero max|y|): how far x is from y, relative to y's largest entry.
double relativeDifference(const Eigen::MatrixXd& x, const Eigen::MatrixXd& y);

/// The name of the rows that hand the in-house formation an engine's compiled
/// masses, CMs and inertias (MuJoCo's: "mujoco-mass"): what differs there is not inertia.
std::string massRowName(const std::string& engine);

struct CrossCheck {
  std::vector<CrossCheckRow> rows;
  std::vector<std::string> skipped;  ///< engines that cannot take this scene, and why
  /// Engines whose own URDF reading could not be used, why, and that their rows are the Model built in them.
  std::vector<std::string> notes;
  /// Rows, by name, with entries that are eigenmass's own code on this scene
  /// rather than the engine's (EngineCode::dependence): what, per entry. Such
  /// an entry's agreement is not independent evidence; its disagreement still counts.
  std::map<std::string, EquationsDependence> dependent;
};

/// A consistent state of a mechanism, as crosscheck draws them: a random one
/// (randomState) projected onto its loops (positions, then speeds; eqs. (M8),
/// (M9)), drawn again where the projection does not converge (a far branch, a
/// singular position). Throws std::runtime_error after 200 draws that all failed.
void consistentState(const Model& m, std::mt19937& rng, Eigen::VectorXd& q, Eigen::VectorXd& u);

/// `states` random states after the initial one (randomState, seeded `seed`).
/// For a URDF scene, `urdf` must be the options it was loaded with. Each of
/// `plugins` (methods from outside/plugin.hpp) gives its u' at the same
/// states: a row against the in-house u' (named as the plugin) and one
/// against each engine's ("<plugin>/<engine>").
CrossCheck crossCheck(const Scene& scene, const UrdfOptions& urdf, int states, unsigned seed,
                      const std::vector<Method>& plugins = {});

}  // namespace em
