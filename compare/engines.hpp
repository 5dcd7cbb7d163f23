#pragma once
/// Runs one method on its engine (the one dispatch point: the in-house
/// integrators, or the engine's row, reference/engine.hpp), and the one place
/// where a scene's run defaults and the reference's defaults apply.
#include <optional>
#include <string>
#include <vector>

#include "io/scene.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// The output grid as asked for: an absent part means "the scene's".
struct Grid {
  std::optional<double> t_end, output_dt;
};

/// `spec` on the grid asked for, the scene's where nothing was asked
/// (simulate.t_end, simulate.output_dt): the one place scene defaults apply.
RunSpec onGrid(RunSpec spec, const Scene& scene, const Grid& grid);

/// The method of the engine whose row says it is the reference when nothing
/// else is asked (EngineRoles::reference, solver/registry.hpp).
Method referenceMethod();

/// The reference run of `method` when nothing else is asked: its engine's
/// adaptive integrator (Simbody RK-Merson, in-house rk8pd) at kReferenceTol.
RunSpec defaultReferenceSpec(Method method = referenceMethod());

/// The integrator an engine runs when the user names none; a tolerance given
/// alone selects its adaptive one (the registry's engine table).
Integrator chosenIntegrator(Engine engine, bool tolerance_given);

/// Refuse a scene whose equations at t = 0 are not finite (a mass, inertia or
/// offset too large for double precision) or whose A is singular there,
/// naming the file (and a locked gimbal). Commands call it before any run.
void checkInitialState(const Scene& scene);

/// Run `spec` on its engine (its settings were checked where it was made: checked()).
Trajectory runTrajectory(const Model& m, const CheckedRunSpec& spec);

/// What engine `e` does to this scene that bounds its agreement with the
/// exact equations (its row's scene_note), or "" (the in-house engine: none).
std::string engineSceneNote(Engine e, const Model& m);
/// Why method `method` cannot take this scene at all, or "" when it can: an
/// engine's refusal (a joint kind it has no mapping for), or a mechanism for a
/// method whose u' is a tree's (MethodInfo::tree_only) or for any engine (no
/// engine maps loops, point springs or drives yet).
std::string methodRefusal(Method method, const Model& m);
/// Why engine `e` cannot run the mechanism `m` (its row's mechanism_refusal,
/// or that its row maps none, naming the rows that do), "" when it can or `m`
/// is a tree: an engine never runs a mechanism as the tree it would be without its loops.
std::string mechanismRefusal(Engine e, const Model& m);
/// Throws std::invalid_argument "method: why" when `method` cannot take `m`.
void requireMethodTakes(Method method, const Model& m);
/// Throws std::invalid_argument where the engine of `spec` would not run it
/// as asked on `m` (EngineCode::settings_refusal), naming the option.
void requireSettingsTaken(const RunSpec& spec, const Model& m);
/// Both, and for an in-house run what its integrator cannot run on `m`
/// (refuseUnrunnable: a controller IDA does not form, a step that does not
/// divide its period): every check a run makes, before any run starts.
void requireRunnable(const RunSpec& spec, const Model& m);

/// Equations at the initial state, in the source's order. For a mechanism,
/// udot is the constrained u' and the closures come with it (theory.md eq. (M7)).
struct Equations {
  int nq = 0, nu = 0;
  Eigen::MatrixXd A;
  Eigen::VectorXd B, udot, eigenvalues;
  double kinetic = 0, potential = 0;
  bool has_loops = false;
  Eigen::MatrixXd G;          ///< (loop_rows x nu), columns in the file's order
  Eigen::VectorXd g, lambda;  ///< (loop_rows): the gaps and the multipliers
  int rank = 0;               ///< of G A^-1 G^T
};
/// At the initial state, or at (q, u) in internal order (the Python module's
/// equations at any state): the same code, so the CLI and the module agree.
Equations inhouseEquations(const Model& m);
Equations inhouseEquations(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u);
/// The same from engine `e` (its row's model; throws std::invalid_argument
/// for an engine that gives no equations at a state).
Equations engineEquations(const Model& m, Engine e);
Equations engineEquations(const Model& m, Engine e, const Eigen::VectorXd& q, const Eigen::VectorXd& u);
/// The engines whose rows give equations at a state, the in-house one first.
std::vector<Engine> enginesWithEquations();

}  // namespace em
