#pragma once
/// Wittenburg's direct formation of the equations of motion A u' = B on a
/// preallocated workspace (docs/theory.md §3–6; paper eqs. (1)–(4), (18)).
/// The dense K, K_T and their rates, the oracles of formA and formAdot, live
/// with the tests (tests/solver/dense_oracles.hpp).
#include <vector>

#include "solver/joint.hpp"
#include "solver/workspace.hpp"

namespace em {


/// Orientations, axes, positions, velocities at (q, u).  // q: (nq), u: (nu)
void formKinematics(const Model& m, const double* q, const double* u, Workspace& ws);
/// Kinetic and potential energy into ws.kinetic, ws.potential (needs
/// formKinematics): where a sample or a check reads them, not in every evaluation.
void formEnergies(const Model& m, const double* q, Workspace& ws);
/// Subtree masses mu, barycentric s, K's diagonal blocks Kd, first moments S
/// and composite inertias I_k, all O(n) bottom-up (needs formKinematics).
void formSubtrees(const Model& m, Workspace& ws);
/// A = (P^T T) K (P^T T)^T (paper eq. (2)) in O(n * depth) from the subtree
/// sums: A_ab = (p_a, o_j x p_a) . (I_k p_b + o_k x c_b, c_b), c_b = p_b x S_k,
/// for a of body j, b of body k, j = k or an ancestor (docs/theory.md §4;
/// needs formSubtrees).  // -> ws.A (nu x nu)
void formA(const Model& m, Workspace& ws);
/// B = -(P^T T)[K T^T f + M'] + Q (paper eq. (18)), K phi by multiplyK
/// (needs formSubtrees).  // -> ws.B (nu)
void formB(const Model& m, const double* q, const double* u, Workspace& ws);
/// Kx = K x in O(n) from K's barycentric blocks, without K (needs
/// formSubtrees; uses ws.z, ws.y as scratch).  // x, Kx: (3n)
void multiplyK(const Model& m, const Eigen::VectorXd& x, Workspace& ws, Eigen::VectorXd& Kx);
/// Subtree momenta L, S' and I' (needs formSubtrees), O(n).
void formSubtreeRates(const Model& m, Workspace& ws);
/// A' in O(n depth): formA's product rule (docs/theory.md §6; needs
/// formSubtreeRates).  // -> ws.Adot (nu x nu)
void formAdot(const Model& m, Workspace& ws);
/// Kinematics, subtrees, A (unless with_A is false: a method that never reads
/// A), B, and A' when asked; not the energies (formEnergies).
void formEquations(const Model& m, const double* q, const double* u, Workspace& ws,
                   bool with_Adot = false, bool with_A = true);
/// A workspace holding the equations (A, B) and the energies at the model's initial state (q0, u0).
Workspace equationsAtStart(const Model& m);
/// Total potential energy (gravity + springs) at q, using ws's CM positions.
double potentialEnergy(const Model& m, const double* q, const Workspace& ws);
/// cond(A) = largest / smallest eigenvalue of a symmetric A (Inf when the
/// smallest is <= 0, NaN when A is not finite). Allocates: for reports.
double conditionNumber(const Eigen::MatrixXd& A);
/// q' from u for all joints.  // q, u -> qdot (nq)
void formQdot(const Model& m, const double* q, const double* u, double* qdot);
/// Every quaternion joint's q to unit length.  // q: (nq)
void normalizeQuaternions(const Model& m, double* q);

}  // namespace em
