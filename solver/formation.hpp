#pragma once
/// Wittenburg's direct formation of the equations of motion A u' = B on a
/// preallocated workspace (docs/theory.md §3–6; paper eqs. (1)–(4), (18)).
/// The dense K, K_T and their rates, the oracles of formA and formAdot, live
/// with the tests (tests/solver/dense_oracles.hpp).
#include <vector>

#include "solver/joint.hpp"
#include "solver/model.hpp"

namespace em {

/// Per-evaluation scratch (Pinocchio's Data, MuJoCo's mjData). Sized once from
/// the model; evaluations never allocate. All vectors in the world frame,
/// bodies in internal (regular) order.
struct Workspace {
  explicit Workspace(const Model& m);

  std::vector<Mat3> R;      ///< R_i: world <- body i
  std::vector<Mat3> J_w;    ///< inertia of body i about its CM, world frame
  std::vector<Vec3> omega;  ///< omega_i: angular velocity of body i
  std::vector<Vec3> b;      ///< l_ii = -R_i c_i: joint point i -> CM i
  std::vector<Vec3> d;      ///< d_i = R_p (a_i - c_p): parent's joint point -> joint point i (0 for roots)
  std::vector<Vec3> o;      ///< position of joint point i
  std::vector<Vec3> vo;     ///< velocity of joint point i
  std::vector<Vec3> v_rel;  ///< v_rel,i: joint point i's sliding velocity relative to its parent (0 unless it slides)
  std::vector<Vec3> r;      ///< position of CM i
  std::vector<Vec3> v;      ///< velocity of CM i
  std::vector<Vec3> s;      ///< s_k = sum over subtree(k) of m_i l_ki
  std::vector<double> mu;   ///< mu_k: mass of subtree(k)
  std::vector<Mat3> Kd;     ///< K_kk: the diagonal blocks of K
  std::vector<Vec3> S;      ///< S_k = sum over subtree(k) of m_i (r_i - o_k): first moment about joint k
  std::vector<Mat3> IC;     ///< I_k: inertia of subtree(k) about joint point k (composite)
  std::vector<Vec3> z, y;   ///< O(n) K phi: z_k = sum over subtree(k) of phi_i x s_i; y_k over ancestors
  std::vector<Vec3> L;      ///< L_k = sum over subtree(k) of m_i v_i (for A')
  std::vector<Mat3> JW, Gamma;  ///< sums over subtree(k) of J_i' and Gamma_k = of m_i [k(v_i, rho_i) + k(rho_i, v_i)] (theory.md §6)
  std::vector<Vec3> S_dot;  ///< S_k'
  std::vector<Mat3> IC_dot; ///< I_k'
  std::vector<Vec3> e;      ///< e_i: velocity-product part of joint point i's acceleration
  std::vector<Vec3> h;      ///< h_i: velocity-product part of CM i's acceleration
  std::vector<Vec3> F;      ///< F_k = sum over subtree(k) of m_i (h_i - g)
  std::vector<Vec3> tau;    ///< tau_i: phi's part of joint point i's acceleration (sliding scenes)
  std::vector<Vec3> F_slide;  ///< F~_k: F_k with phi's part, what a slide's row of B projects (sliding scenes)
  Eigen::Matrix3Xd P;       ///< the paper's p: world axes p_jk as columns (block diagonal, stored 3 x nu)
  Eigen::Matrix3Xd Pdot;    ///< axis rates p_jk'  (3 x nu)
  Eigen::MatrixXd A, Adot;  ///< mass matrix and its time derivative  (nu x nu)
  Eigen::VectorXd B;        ///< right-hand side  (nu)
  Eigen::VectorXd phi;      ///< phi = T^T f: velocity-product angular accelerations  (3n)
  Eigen::VectorXd psi;      ///< psi = K phi + M', then T psi  (3n)
  double kinetic = 0, potential = 0;

  double energy() const { return kinetic + potential; }
};

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
/// Q += generalized spring-damper forces -k (q - q_rest) - c u.  // Q: (nu)
void addSpringForces(const Model& m, const double* q, const double* u, Eigen::VectorXd& Q);
/// Power dissipated by the dampers, sum over coordinates of c u^2 >= 0 (dW_diss/dt).  // u: (nu)
double dissipationRate(const Model& m, const double* u);
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
