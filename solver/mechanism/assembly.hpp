#pragma once
/// An assembled start (the scene's simulate.assemble, --assemble; docs/theory.md
/// §15, eqs. (M8), (M9)): a result the caller builds its model from
/// (withInitialState), never a change to the model it was found on.
#include "solver/model.hpp"

namespace em {

/// What assembling a start did: the gaps it found, how far it moved q0 and
/// u0, and the assembled state.
struct Assembly {
  double gap = 0, velocity_gap = 0;  ///< max of |g| and the loops' turns (m or rad), and max |G u| (m/s or rad/s), before
  double moved_q = 0, moved_u = 0;   ///< max |q - q0| (rad or m; quaternion parts), max |u - u0|
  int iterations = 0;                ///< Gauss-Newton steps
  bool converged = false;            ///< max |g| <= tol reached (else q and u are the model's own)
  Eigen::VectorXd q, u;              ///< the assembled start, internal order (nq), (nu)
};
/// q0 onto g = 0, then u0 onto G u = 0: the least change in A's metric.
Assembly assembleStart(const Model& m, double tol, int iterations);

}  // namespace em
