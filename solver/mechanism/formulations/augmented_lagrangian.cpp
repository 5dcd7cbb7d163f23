// The index-3 augmented Lagrangian (docs/theory.md eq. (M13)) as a formulation:
// it brings its own integrator, trapezoidal (solver/augmented_lagrangian.cpp),
// which steps A, B and the loops itself; an evaluation of u' outside it (a
// sample's) takes the multipliers. What its run reports:
#include "solver/mechanism/formulation.hpp"

namespace em {

void augmentedLagrangianFigures(const LoopStats& s, const LoopOptions& o, std::vector<FormulationFigure>& out) {
  // Its Newton runs once per step.
  out.push_back({"newton_steps", double(s.newton_solves), true});
  out.push_back({"newton_iterations", double(s.newton_iterations), true});
  out.push_back({"newton_unconverged", double(s.newton_unconverged), true});
  out.push_back({"newton_at_roundoff", double(s.newton_at_roundoff), true});
  out.push_back({"newton_tol", o.al_tol});
  out.push_back({"penalty_ratio", o.penalty_ratio});
}

}  // namespace em
