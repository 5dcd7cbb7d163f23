#pragma once
/// Joint kinematics for the four joint kinds (docs/theory.md §1, §3).
#include "solver/model.hpp"

namespace em {

using Axes = Eigen::Matrix<double, 3, Eigen::Dynamic, 0, 3, 3>;  ///< up to 3 axis columns, no heap

/// R_parent,body of the joint at coordinates q.  // q: (nq)  -> (3x3)
Mat3 relativeRotation(const Joint& j, const double* q);

/// World-frame joint axes p_jk as columns, R_p = parent orientation.  // -> (3 x nu)
void worldAxes(const Joint& j, const Mat3& R_p, const double* q, Axes& P);

/// Axis rates p_jk' (columns) from the parent's and the body's angular velocity
/// and the joint's own speeds (gimbal: the intermediate frame).  // -> (3 x nu)
void axisRates(const Joint& j, const Axes& P, const Vec3& omega_p, const Vec3& omega_b,
               const double* u, Axes& Pdot);

/// q' from u: q' = u, except ball: q' = (1/2) (0,u) (x) q (u in the parent frame).
void jointQdot(const Joint& j, const double* q, const double* u, double* qdot);

}  // namespace em
