#pragma once
/// Joint kinematics for the six joint kinds (docs/theory.md §1, §3, §12): the
/// rotational kinds turn about the joint point; prismatic and free slide it.
#include "solver/model.hpp"

namespace em {

using Axes = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 6>;  ///< up to 6 axis columns (free), no heap

/// R_parent,body of the joint at coordinates q.  // q: (nq)  -> (3x3)
Mat3 relativeRotation(const Joint& j, const double* q);

/// Displacement x of the joint point from its rest place, parent frame:
/// prismatic q0 * axis, free (q0, q1, q2), else zero (docs/theory.md §12).  // q: (nq)
Vec3 slideOffset(const Joint& j, const double* q);

/// World-frame joint axes p_jk as columns, R_p = parent orientation: the
/// sliding direction t_jk for the first nt speeds, the rotation axis for the
/// rest (docs/theory.md §12).  // -> (3 x nu)
void worldAxes(const Joint& j, const Mat3& R_p, const double* q, Axes& P);

/// Axis rates p_jk' (columns) from the parent's and the body's angular velocity
/// and the joint's own speeds (gimbal: the intermediate frame; sliding
/// directions turn with the parent).  // -> (3 x nu)
void axisRates(const Joint& j, const Axes& P, const Vec3& omega_p, const Vec3& omega_b,
               const double* u, Axes& Pdot);

/// q' from u: q' = u, except a quaternion (ball, free's rotation):
/// q' = (1/2) (0,w) (x) q (w in the parent frame).
void jointQdot(const Joint& j, const double* q, const double* u, double* qdot);

}  // namespace em
