#pragma once
/// Joint kinematics of every joint kind (docs/theory.md §1, §3, §12), each
/// through its kind's row (solver/model.hpp) and its own file
/// (solver/joints/<kind>.cpp): the rotational part turns about the joint
/// point; prismatic, planar and free joints also slide it.
#include "solver/model.hpp"

namespace em {

/// R_parent,body of the joint at coordinates q.  // q: (nq)  -> (3x3)
Mat3 relativeRotation(const Joint& j, const double* q);

/// Displacement x of the joint point from its rest place, parent frame:
/// prismatic q0 * axis, planar q0 e1 + q1 e2, free (q0, q1, q2), else zero
/// (docs/theory.md §12).  // q: (nq)
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

/// The inverse of relativeRotation and slideOffset: the joint's coordinates
/// from its relative rotation R (parent <- body) and its joint point's
/// displacement x (parent frame), on the branch nearest `near` (angles within
/// pi of it, a quaternion in its hemisphere, a gimbal's middle angle on the
/// nearer of its two branches). What the joint cannot take (a revolute's
/// rotation off its axis, a hinge's x) is dropped: a constraint violation,
/// measured apart (jointSeparation).  // near, q: (nq)
void jointCoordinates(const Joint& j, const Mat3& R, const Vec3& x, const double* near, double* q);

/// The joint's speeds at q from the body's angular velocity relative to its
/// parent, w, and the rate x' of its joint point's displacement, both in the
/// parent frame (the least-squares u where the joint cannot take all of w).  // q: (nq), u: (nu)
void jointSpeeds(const Joint& j, const double* q, const Vec3& w, const Vec3& xdot, double* u);

/// The part of x the joint cannot take: all of it, but a prismatic joint's
/// slide along its axis, a planar joint's in its plane and a free joint's (m).
double jointSeparation(const Joint& j, const Vec3& x);

}  // namespace em
