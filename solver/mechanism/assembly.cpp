// An assembled start (docs/theory.md §15, eqs. (M8), (M9)).
#include "solver/mechanism/assembly.hpp"

#include <algorithm>

#include "solver/formation.hpp"
#include "solver/mechanism/projection.hpp"

namespace em {

Assembly assembleStart(const Model& m, double tol, int iterations) {
  Assembly a;
  a.q = m.q0(), a.u = m.u0();
  Eigen::VectorXd q = a.q, u = a.u;
  Workspace ws(m);
  formKinematics(m, q.data(), u.data(), ws);
  LoopState before(m);
  formLoops(m, ws, u.data(), before);
  // The turn counts too: a hinge whose axes are opposed has g = 0 on its direction rows and is
  // pi rad open (issue 73, item 14: the message said "gap 1.11e-16").
  a.gap = std::max({before.g.size() ? before.g.cwiseAbs().maxCoeff() : 0.0, before.position_m, before.position_rad});
  LoopProjector project(m);
  const LoopProjector::Result r = project.positions(m, ws, q.data(), u.data(), tol, iterations);
  a.iterations = r.iterations;
  a.converged = r.converged && r.finite;
  if (!a.converged) return a;
  a.velocity_gap = before.Gu.size() ? before.Gu.cwiseAbs().maxCoeff() : 0.0;
  project.velocities(u.data());
  a.moved_q = (q - a.q).cwiseAbs().maxCoeff();
  a.moved_u = (u - a.u).cwiseAbs().maxCoeff();
  a.q = q, a.u = u;
  return a;
}

}  // namespace em
