#pragma once
/// The applied forces beyond gravity (docs/theory.md §5, §15): the joints'
/// spring-dampers, the drives and the point spring-dampers, as generalized
/// forces (eq. (M5)), their potential and the power they take out (eq. (M6)).
/// The formation adds them to B; they read a Workspace whose kinematics are formed.
#include "solver/point_kinematics.hpp"

namespace em {

/// Q += generalized spring-damper forces -k (q - q_rest) - c u.  // Q: (nu)
void addSpringForces(const Model& m, const double* q, const double* u, Eigen::VectorXd& Q);
/// Power dissipated by the joint dampers, sum over coordinates of c u^2 >= 0 (dW_diss/dt on a tree).  // u: (nu)
double dissipationRate(const Model& m, const double* u);

/// Q += the joint springs', the drives' and the point spring-dampers'
/// generalized forces (theory.md eq. (M5)).  // q: (nq), u, Q: (nu)
void addAppliedForces(const Model& m, const Workspace& ws, const double* q, const double* u, Eigen::VectorXd& Q);
/// Q += the drives' and the point spring-dampers' generalized forces alone
/// (what a tree's u' from outside lacks: a plugin's tau).  // Q: (nu)
void addMechanismForces(const Model& m, const Workspace& ws, Eigen::VectorXd& Q);
/// The applied forces' damping and stiffness matrices, C += -dQ/du and
/// K += -dQ/dq (theory.md eq. (M13a)): the joints' c and k on the diagonal, and
/// for a point spring-damper of tension T along n between its points, d = x_b - x_a
/// moving as d' = J_d u,  C += c J_d^T n n^T J_d  and
/// K += J_d^T (k n n^T + (T/l)(I - n n^T)) J_d, the derivatives of J_d itself
/// left out (the augmented Lagrangian's tangent; q' = u, no quaternion). The
/// drives are constant: nothing. J: scratch (3 x nu).
void addForceTangent(const Model& m, const Workspace& ws, Eigen::MatrixXd& C, Eigen::MatrixXd& K, Eigen::MatrixXd& J);
/// The force on a's point of point spring-damper `s` whose points are at pa
/// and pb, moving at va and vb (world): tension k (l - length) + c l' along
/// the line from a's point to b's; -f acts on b's; zero where the points
/// coincide (io keeps them apart at the start). The engines that apply point
/// springs as forces (ODE, Bullet, DART) take it from their own states.
Vec3 pointSpringForce(const PointSpring& s, const Vec3& pa, const Vec3& va, const Vec3& pb, const Vec3& vb);
/// Potential of the point springs, sum of k (l - length)^2 / 2.
double pointSpringPotential(const Model& m, const Workspace& ws);
/// dW_diss/dt: the power the joint and point dampers dissipate minus the
/// power the drives put in (theory.md eq. (M6)); E + W_diss is conserved.
double nonConservativePower(const Model& m, const Workspace& ws, const double* u);

}  // namespace em
