#pragma once
/// Points fixed in bodies at the formed kinematics (docs/theory.md §15, eqs.
/// (M2), (M3)): where they are, how fast they move, and the Jacobians and
/// velocity-product terms of their motion. What the closures' rows
/// (solver/mechanism/) and the point forces (solver/applied_forces.hpp) are
/// made of; everything here reads a Workspace whose kinematics are formed.
#include "solver/workspace.hpp"

namespace em {

/// A point of a body (or of the ground) at the formed kinematics: world
/// position and velocity.
struct PointMotion {
  Vec3 x = Vec3::Zero(), v = Vec3::Zero();
};
PointMotion pointMotion(const Workspace& ws, const Attachment& p);

/// R_i of `body`, the identity for the ground (-1); its angular velocity, 0 for the ground.
inline Mat3 rotationOf(const Workspace& ws, int body) { return body < 0 ? Mat3::Identity() : ws.R[body]; }
inline Vec3 omegaOf(const Workspace& ws, int body) { return body < 0 ? Vec3::Zero() : ws.omega[body]; }

/// Calls visit(j, column) for every speed j on body's path to the ground, with
/// the column of J for the world point x (eq. (M2)): the one walk of the point
/// Jacobian and of a point force's J^T f.
template <class Visit>
void forPointColumns(const Model& m, const Workspace& ws, int body, const Vec3& x, Visit&& visit) {
  for (int k = body; k >= 0; k = m.body_parent[k]) {
    const int iu = m.body_iu[k], nt = m.body_nt[k], nu = m.body_nu[k];
    for (int j = iu; j < iu + nt; ++j) visit(j, Vec3(ws.P.col(j)));
    for (int j = iu + nt; j < iu + nu; ++j) visit(j, Vec3(ws.P.col(j).cross(x - ws.o[k])));
  }
}

/// rows += sign * J, J (3 x nu) the Jacobian of the velocity of world point x
/// moving with `body` (x' = J u): over the body's path to the ground, a slide
/// column p_k, a turning column p_k x (x - o_k) (theory.md eq. (M2)).
void addPointJacobian(const Model& m, const Workspace& ws, int body, const Vec3& x, double sign,
                      Eigen::Ref<Eigen::MatrixXd> rows);
/// rows += sign * J_w, J_w (3 x nu) the Jacobian of the body's angular velocity.
void addAngularJacobian(const Model& m, const Workspace& ws, int body, double sign, Eigen::Ref<Eigen::MatrixXd> rows);
/// x'' at u' = 0 for the world point x moving with `body` at velocity xdot: J' u
/// (theory.md eq. (M3)); 0 for the ground.  // u: (nu)
Vec3 pointBias(const Model& m, const Workspace& ws, const double* u, int body, const Vec3& x, const Vec3& xdot);
/// omega' at u' = 0: J_w' u; 0 for the ground.
Vec3 angularBias(const Model& m, const Workspace& ws, const double* u, int body);

}  // namespace em
