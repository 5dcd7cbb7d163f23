#pragma once
/// Runs one method on either engine (the one place that knows both), and the
/// one place where a scene's run defaults and the reference's defaults apply
/// (the engines' integrators themselves are the registry's engine table).
#include <optional>
#include <string>

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

/// The reference run of `method` when nothing else is asked: its engine's
/// adaptive integrator (Simbody RK-Merson, in-house rk8pd) at kReferenceTol.
RunSpec referenceRun(Method method = Method::Simbody);

/// The integrator an engine runs when the user names none; a tolerance given
/// alone selects its adaptive one (the registry's engine table).
Integrator chosenIntegrator(Engine engine, bool tolerance_given);

/// Refuse a scene whose equations at t = 0 are not finite (a mass, inertia or
/// offset too large for double precision) or whose A is singular there,
/// naming the file (and a locked gimbal). Commands call it before any run.
void checkInitialState(const Scene& scene);

/// Run `spec` on its engine. Throws for settings that cannot be run.
Trajectory runMethod(const Model& m, const RunSpec& spec);

/// Equations at the initial state, in the source's order.
struct Equations {
  int nq = 0, nu = 0;
  Eigen::MatrixXd A;
  Eigen::VectorXd B, udot, eigenvalues;
  double kinetic = 0, potential = 0;
};
Equations inhouseEquations(const Model& m);
Equations simbodyEquations(const Model& m);

}  // namespace em
