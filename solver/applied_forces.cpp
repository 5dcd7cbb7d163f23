// The applied forces beyond gravity (docs/theory.md §5, §15).
#include "solver/applied_forces.hpp"

namespace em {

void addSpringForces(const Model& m, const double* q, const double* u, Eigen::VectorXd& Q) {
  for (const Body& body : m.bodies) {
    if (!body.joint.has_spring) continue;
    const Spring& sp = body.joint.spring;
    for (int k = 0; k < body.nu(); ++k)
      Q[body.iu + k] += -sp.k[k] * (q[body.iq + k] - sp.q_rest[k]) - sp.c[k] * u[body.iu + k];
  }
}

double dissipationRate(const Model& m, const double* u) {
  double P = 0;
  for (const Body& body : m.bodies) {
    if (!body.joint.has_spring) continue;
    for (int k = 0; k < body.nu(); ++k) P += body.joint.spring.c[k] * u[body.iu + k] * u[body.iu + k];
  }
  return P;
}

namespace {

// A point spring's line at the formed kinematics: a's and b's points, the unit
// vector from a to b, the length and its rate.
struct SpringLine {
  PointMotion a, b;
  Vec3 n;
  double l = 0, ldot = 0;
};
SpringLine springLine(const Workspace& ws, const PointSpring& s) {
  SpringLine L{pointMotion(ws, s.a), pointMotion(ws, s.b), Vec3::Zero()};
  const Vec3 d = L.b.x - L.a.x;
  L.l = d.norm();
  L.n = L.l > 0 ? Vec3(d / L.l) : Vec3::Zero();  // coincident points: no direction, no force (io refuses them at the start)
  L.ldot = L.n.dot(L.b.v - L.a.v);
  return L;
}

}  // namespace

void addAppliedForces(const Model& m, const Workspace& ws, const double* q, const double* u, Eigen::VectorXd& Q) {
  if (m.has_springs) addSpringForces(m, q, u, Q);
  addMechanismForces(m, ws, Q);
}

void addMechanismForces(const Model& m, const Workspace& ws, Eigen::VectorXd& Q) {
  if (m.has_control) Q += ws.control;  // the controllers' torques (theory.md eq. (C1))
  if (m.has_drives)
    for (const Body& b : m.bodies)
      if (b.joint.torque.size()) Q.segment(b.iu, b.nu()) += b.joint.torque;
  for (const PointSpring& s : m.point_springs) {
    const SpringLine L = springLine(ws, s);
    const double tension = s.k * (L.l - s.length) + s.c * L.ldot;  // pulls the points together when > 0
    // The force on b is -tension n, on a +tension n; Q = sum J^T f (eq. (M5)).
    // (A named pair, not a structured binding: C++17 cannot capture a binding in a lambda, and clang refuses it.)
    for (const auto& end : {std::pair<const Attachment*, Vec3>{&s.a, tension * L.n}, {&s.b, -tension * L.n}}) {
      const Attachment* att = end.first;
      const Vec3 f = end.second;
      if (att->body < 0) continue;
      const Vec3 x = att == &s.a ? L.a.x : L.b.x;
      forPointColumns(m, ws, att->body, x, [&](int j, const Vec3& col) { Q[j] += col.dot(f); });
    }
  }
}

void addForceTangent(const Model& m, const Workspace& ws, Eigen::MatrixXd& C, Eigen::MatrixXd& K, Eigen::MatrixXd& J) {
  if (m.has_springs)
    for (const Body& b : m.bodies) {
      if (!b.joint.has_spring) continue;
      const Spring& sp = b.joint.spring;
      for (int j = 0; j < b.nu(); ++j) {
        C(b.iu + j, b.iu + j) += sp.c[j];
        K(b.iu + j, b.iu + j) += sp.k[j];
      }
    }
  for (const PointSpring& s : m.point_springs) {
    const SpringLine L = springLine(ws, s);
    if (L.l == 0) continue;  // no direction, no force
    J.setZero();
    addPointJacobian(m, ws, s.b.body, L.b.x, 1.0, J);  // J_d = J_b - J_a (the ground's rows stay 0)
    addPointJacobian(m, ws, s.a.body, L.a.x, -1.0, J);
    const double tension = s.k * (L.l - s.length) + s.c * L.ldot;
    const Mat3 nn = L.n * L.n.transpose();
    const Mat3 stiffness = s.k * nn + (tension / L.l) * (Mat3::Identity() - nn);
    for (int a = 0; a < 3; ++a)  // J^T S J as nine outer products: no temporary
      for (int b = 0; b < 3; ++b) {
        K.noalias() += stiffness(a, b) * J.row(a).transpose() * J.row(b);
        if (s.c != 0) C.noalias() += (s.c * nn(a, b)) * J.row(a).transpose() * J.row(b);
      }
  }
}

Vec3 pointSpringForce(const PointSpring& s, const Vec3& pa, const Vec3& va, const Vec3& pb, const Vec3& vb) {
  const Vec3 d = pb - pa;
  const double l = d.norm();
  if (l == 0) return Vec3::Zero();
  const Vec3 n = d / l;
  return (s.k * (l - s.length) + s.c * n.dot(vb - va)) * n;
}

double pointSpringPotential(const Model& m, const Workspace& ws) {
  double V = 0;
  for (const PointSpring& s : m.point_springs) {
    const double e = springLine(ws, s).l - s.length;
    V += 0.5 * s.k * e * e;
  }
  return V;
}

double nonConservativePower(const Model& m, const Workspace& ws, const double* u) {
  double P = dissipationRate(m, u);
  for (const PointSpring& s : m.point_springs) {
    if (s.c == 0) continue;
    const double ldot = springLine(ws, s).ldot;
    P += s.c * ldot * ldot;
  }
  if (m.has_drives)
    for (const Body& b : m.bodies)
      if (b.joint.torque.size()) P -= b.joint.torque.dot(Eigen::Map<const Eigen::VectorXd>(u + b.iu, b.nu()));
  if (m.has_control) P -= ws.control.dot(Eigen::Map<const Eigen::VectorXd>(u, m.nu));  // theory.md eq. (C3)
  return P;
}

}  // namespace em
