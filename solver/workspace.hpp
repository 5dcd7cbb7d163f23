#pragma once
/// The per-evaluation scratch of the formation and of everything that reads
/// its kinematics (solver/formation.hpp forms it; solver/point_kinematics.hpp,
/// solver/applied_forces.hpp and solver/mechanism/ read it).
#include <vector>

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
  Eigen::VectorXd control;  ///< the joint controllers' torques, set by the run before forming (theory.md §18); 0 at a bare state  (nu, or 0 without control)
  Eigen::VectorXd phi;      ///< phi = T^T f: velocity-product angular accelerations  (3n)
  Eigen::VectorXd psi;      ///< psi = K phi + M', then T psi  (3n)
  double kinetic = 0, potential = 0;

  double energy() const { return kinetic + potential; }
};

}  // namespace em
