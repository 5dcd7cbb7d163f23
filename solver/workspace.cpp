#include "solver/workspace.hpp"

namespace em {

Workspace::Workspace(const Model& m) {
  const int n = m.n(), nu = m.nu;
  for (auto* v : {&omega, &b, &d, &o, &vo, &v_rel, &r, &v, &s, &e, &h, &F, &F_slide, &tau, &S, &z, &y, &L, &S_dot}) v->assign(n, Vec3::Zero());
  for (auto* M : {&Kd, &IC, &JW, &Gamma, &IC_dot}) M->assign(n, Mat3::Zero());
  R.assign(n, Mat3::Identity());
  J_w.assign(n, Mat3::Zero());
  mu.assign(n, 0.0);
  P = Eigen::Matrix3Xd::Zero(3, nu);
  Pdot = Eigen::Matrix3Xd::Zero(3, nu);
  A = Eigen::MatrixXd::Zero(nu, nu);
  Adot = Eigen::MatrixXd::Zero(nu, nu);
  B = Eigen::VectorXd::Zero(nu);
  control = Eigen::VectorXd::Zero(m.has_control ? nu : 0);
  phi = Eigen::VectorXd::Zero(3 * n);
  psi = Eigen::VectorXd::Zero(3 * n);
}

}  // namespace em
