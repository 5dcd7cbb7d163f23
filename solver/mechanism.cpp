// Closures, point forces and drives (docs/theory.md §15).
#include "solver/mechanism.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "solver/text.hpp"

namespace em {

namespace {

Mat3 rotationOf(const Workspace& ws, int body) { return body < 0 ? Mat3::Identity() : ws.R[body]; }
Vec3 omegaOf(const Workspace& ws, int body) { return body < 0 ? Vec3::Zero() : ws.omega[body]; }

// Two unit vectors perpendicular to unit n, fixed by n alone.
void perpendicularPair(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 seed = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  t1 = n.cross(seed).normalized();
  t2 = n.cross(t1);
}

// One row that keeps unit e (turning with body a) perpendicular to unit f
// (turning with body b): g = e.f, G = (e x f)^T (J_w,a - J_w,b) (eq. (M4)).
struct PairRow {
  Vec3 e, f;
};

}  // namespace

const std::vector<FormulationInfo>& formulationTable() {
  static const std::vector<FormulationInfo> table = {
      {Formulation::Baumgarte, "baumgarte", "Lagrange multipliers at acceleration level, Baumgarte's alpha and beta (default 0: the raw drift)"},
      {Formulation::Projection, "projection", "the same, then after every accepted step q onto g = 0 (Gauss-Newton in A's metric) and u onto G u = 0"},
      {Formulation::UdwadiaKalaba, "udwadia-kalaba",
       "u' = a + M (G M)^+ (b - G a) with M M^T = A^-1 from the method's own factors (eigenfactors: M = C^T Lambda^(-1/2)), "
       "Baumgarte's b, no projection"},
      {Formulation::CoordinatePartitioning, "coordinate-partitioning",
       "Wehage-Haug: the independent coordinates integrated, the dependent ones by Newton on g = 0 at every evaluation; "
       "re-partitioned where the pivots degrade tenfold"},
      {Formulation::AugmentedLagrangian, "augmented-lagrangian",
       "index-3 augmented Lagrangian with mass-orthogonal projections (Bayo, Garcia de Jalon: ALI3-P), under its own "
       "integrator trapezoidal (fixed step dt)"}};
  return table;
}

const char* formulationName(Formulation f) {
  for (const FormulationInfo& r : formulationTable())
    if (r.id == f) return r.name;
  return "?";
}

bool findFormulation(const std::string& name, Formulation& out) {
  for (const FormulationInfo& r : formulationTable())
    if (name == r.name) {
      out = r.id;
      return true;
    }
  return false;
}

PointMotion pointMotion(const Workspace& ws, const Attachment& p) {
  if (p.body < 0) return {p.point, Vec3::Zero()};
  const Vec3 rho = ws.R[p.body] * p.point;
  return {ws.r[p.body] + rho, ws.v[p.body] + ws.omega[p.body].cross(rho)};
}

namespace {

// Calls visit(j, column) for every speed j on body's path to the ground, with
// the column of J for the world point x (eq. (M2)): the one walk of the point
// Jacobian and of a point force's J^T f.
template <class Visit>
void forPointColumns(const Model& m, const Workspace& ws, int body, const Vec3& x, Visit&& visit) {
  for (int k = body; k >= 0; k = m.body_parent[k]) {
    const int iu = m.body_iu[k], nt = m.body_nt[k], nu = m.body_nu[k];
    for (int j = iu; j < iu + nt; ++j) visit(j, Vec3(ws.P.col(j)));
    for (int j = iu + nt; j < iu + nu; ++j) visit(j, Vec3(ws.P.col(j).cross(x - ws.o[k])));
  }
}

}  // namespace

void addPointJacobian(const Model& m, const Workspace& ws, int body, const Vec3& x, double sign,
                      Eigen::Ref<Eigen::MatrixXd> rows) {
  forPointColumns(m, ws, body, x, [&](int j, const Vec3& col) { rows.col(j) += sign * col; });
}

void addAngularJacobian(const Model& m, const Workspace& ws, int body, double sign, Eigen::Ref<Eigen::MatrixXd> rows) {
  for (int k = body; k >= 0; k = m.body_parent[k]) {
    const int iu = m.body_iu[k], nt = m.body_nt[k], nu = m.body_nu[k];
    for (int j = iu + nt; j < iu + nu; ++j) rows.col(j) += sign * ws.P.col(j);
  }
}

Vec3 pointBias(const Model& m, const Workspace& ws, const double* u, int body, const Vec3& x, const Vec3& xdot) {
  Vec3 a = Vec3::Zero();
  for (int k = body; k >= 0; k = m.body_parent[k]) {
    const int iu = m.body_iu[k], nt = m.body_nt[k], nu = m.body_nu[k];
    for (int j = iu; j < iu + nt; ++j) a += ws.Pdot.col(j) * u[j];
    for (int j = iu + nt; j < iu + nu; ++j)
      a += (ws.Pdot.col(j).cross(x - ws.o[k]) + ws.P.col(j).cross(xdot - ws.vo[k])) * u[j];
  }
  return a;
}

Vec3 angularBias(const Model& m, const Workspace& ws, const double* u, int body) {
  Vec3 a = Vec3::Zero();
  for (int k = body; k >= 0; k = m.body_parent[k]) {
    const int iu = m.body_iu[k], nt = m.body_nt[k], nu = m.body_nu[k];
    for (int j = iu + nt; j < iu + nu; ++j) a += ws.Pdot.col(j) * u[j];
  }
  return a;
}

LoopState::LoopState(const Model& m)
    : g(Eigen::VectorXd::Zero(m.loop_rows)), Gu(Eigen::VectorXd::Zero(m.loop_rows)), c(Eigen::VectorXd::Zero(m.loop_rows)),
      G(Eigen::MatrixXd::Zero(m.loop_rows, m.nu)), Jw(3, m.nu), turn(m.loops.size(), 0.0) {}

namespace {

// Rows r..r+2: a's point meets b's (eqs. (M1)-(M3)).
void ballRows(const Model& m, const Workspace& ws, const double* u, const Loop& l, int r, LoopState& ls) {
  const PointMotion pa = pointMotion(ws, l.a), pb = pointMotion(ws, l.b);
  ls.g.segment<3>(r) = pa.x - pb.x;
  auto rows = ls.G.middleRows(r, 3);
  if (l.a.body >= 0) addPointJacobian(m, ws, l.a.body, pa.x, 1.0, rows);
  if (l.b.body >= 0) addPointJacobian(m, ws, l.b.body, pb.x, -1.0, rows);
  ls.c.segment<3>(r) = (l.a.body < 0 ? Vec3::Zero() : pointBias(m, ws, u, l.a.body, pa.x, pa.v)) -
                       (l.b.body < 0 ? Vec3::Zero() : pointBias(m, ws, u, l.b.body, pb.x, pb.v));
}

// The relative turn of a loop's bodies: J_w,a - J_w,b into ls.Jw, and
// omega_a, omega_b and alpha_a - alpha_b, shared by its direction rows.
struct RelativeTurn {
  Vec3 wa, wb, alpha;
};
RelativeTurn relativeTurn(const Model& m, const Workspace& ws, const double* u, const Loop& l, LoopState& ls) {
  ls.Jw.setZero();
  if (l.a.body >= 0) addAngularJacobian(m, ws, l.a.body, 1.0, ls.Jw);
  if (l.b.body >= 0) addAngularJacobian(m, ws, l.b.body, -1.0, ls.Jw);
  return {omegaOf(ws, l.a.body), omegaOf(ws, l.b.body),
          Vec3((l.a.body < 0 ? Vec3::Zero() : angularBias(m, ws, u, l.a.body)) -
               (l.b.body < 0 ? Vec3::Zero() : angularBias(m, ws, u, l.b.body)))};
}

// Row r: e (with a) stays perpendicular to f (with b) (eq. (M4)).
void pairRow(const RelativeTurn& turn, const PairRow& p, int r, LoopState& ls) {
  const Vec3 n = p.e.cross(p.f);
  ls.g[r] = p.e.dot(p.f);
  ls.G.row(r).noalias() = n.transpose() * ls.Jw;
  const Vec3 ndot = turn.wa.cross(p.e).cross(p.f) + p.e.cross(turn.wb.cross(p.f));
  ls.c[r] = n.dot(turn.alpha) + ndot.dot(turn.wa - turn.wb);
}

// The angle between unit vectors e and f, accurate near 0 (theory.md eq. (M4b)).
double angleBetween(const Vec3& e, const Vec3& f) { return std::atan2(e.cross(f).norm(), e.dot(f)); }

// The angle of the rotation Q (accurate near 0: from its skew part and its trace).
double rotationAngle(const Mat3& Q) {
  const Vec3 s(Q(2, 1) - Q(1, 2), Q(0, 2) - Q(2, 0), Q(1, 0) - Q(0, 1));
  return std::atan2(0.5 * s.norm(), 0.5 * (Q.trace() - 1));
}

}  // namespace

void formLoops(const Model& m, const Workspace& ws, const double* u, LoopState& ls) {
  ls.G.setZero();
  int r = 0;
  for (size_t i = 0; i < m.loops.size(); ++i) {
    const Loop& l = m.loops[i];
    ballRows(m, ws, u, l, r, ls);
    r += 3;
    if (l.type == LoopType::Ball) continue;
    const Mat3 Ra = rotationOf(ws, l.a.body), Rb = rotationOf(ws, l.b.body);
    const RelativeTurn turn = relativeTurn(m, ws, u, l, ls);
    if (l.type == LoopType::Hinge) {
      Vec3 t1, t2;
      perpendicularPair(l.axis_b, t1, t2);
      const Vec3 e = Ra * l.axis_a;
      pairRow(turn, {e, Rb * t1}, r++, ls);
      pairRow(turn, {e, Rb * t2}, r++, ls);
      ls.turn[i] = angleBetween(e, Rb * l.axis_b);
    } else {  // weld
      const Mat3 A = Ra * l.rel;  // b's frame as a holds it
      for (int k = 0; k < 3; ++k) pairRow(turn, {A.col(k), Rb.col((k + 1) % 3)}, r++, ls);
      ls.turn[i] = rotationAngle(A.transpose() * Rb);
    }
  }
  ls.Gu.noalias() = ls.G * Eigen::Map<const Eigen::VectorXd>(u, m.nu);
  ls.position_m = ls.position_rad = ls.velocity_m = ls.velocity_rad = 0;
  r = 0;
  for (size_t i = 0; i < m.loops.size(); ++i) {
    const Loop& l = m.loops[i];
    ls.position_m = std::max(ls.position_m, ls.g.segment<3>(r).cwiseAbs().maxCoeff());
    ls.velocity_m = std::max(ls.velocity_m, ls.Gu.segment<3>(r).cwiseAbs().maxCoeff());
    ls.position_rad = std::max(ls.position_rad, ls.turn[i]);
    const int extra = loopRow(l.type).equations - 3;
    if (extra > 0) {
      ls.velocity_rad = std::max(ls.velocity_rad, ls.Gu.segment(r + 3, extra).cwiseAbs().maxCoeff());
    }
    r += loopRow(l.type).equations;
  }
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
  return P;
}

namespace {

// x = X^+ r by a complete orthogonal decomposition at relative threshold tol; its rank.
int leastNorm(Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>& cod, const Eigen::MatrixXd& X, double tol,
              const Eigen::VectorXd& r, Eigen::VectorXd& x) {
  if (X.rows() == 0) {  // no loops (a tree with point springs or drives): nothing to solve; Eigen's QR of 0 rows crashes
    x.setZero(X.cols());
    return 0;
  }
  cod.setThreshold(tol);
  cod.compute(X);
  x = cod.solve(r);
  return static_cast<int>(cod.rank());
}

}  // namespace

ConstrainedSolve::ConstrainedSolve(const Model& m)
    : S_(m.loop_rows, m.loop_rows), GM_(m.loop_rows, m.nu), r_(m.loop_rows), lambda_(Eigen::VectorXd::Zero(m.loop_rows)),
      w_(m.nu), cod_(m.loop_rows, m.loop_rows), cod_gm_(m.loop_rows, m.nu) {}

// r = b - G a, b = -c - 2 alpha G u - beta^2 g: what the constraint force must add to g''.
void ConstrainedSolve::residual(const LoopState& ls, double alpha, double beta, const Eigen::Ref<const Eigen::VectorXd>& a) {
  r_ = -ls.c - 2.0 * alpha * ls.Gu - beta * beta * ls.g;
  r_.noalias() -= ls.G * a;
}

int ConstrainedSolve::solve(const LoopState& ls, const Eigen::MatrixXd& AinvGt, double alpha, double beta,
                            Eigen::Ref<Eigen::VectorXd> udot) {
  S_.noalias() = ls.G * AinvGt;
  residual(ls, alpha, beta, udot);
  rank_ = leastNorm(cod_, S_, kLoopRankTol, r_, lambda_);
  udot.noalias() += AinvGt * lambda_;
  return rank_;
}

int ConstrainedSolve::solveUdwadiaKalaba(const LoopState& ls, const Eigen::MatrixXd& M, double alpha, double beta,
                                         Eigen::Ref<Eigen::VectorXd> udot) {
  GM_.noalias() = ls.G * M;
  residual(ls, alpha, beta, udot);
  rank_ = leastNorm(cod_gm_, GM_, kLoopRankTolUK, r_, w_);  // the least-norm w with (G M) w = r on G M's range
  udot.noalias() += M * w_;
  return rank_;
}

void ConstrainedSolve::correction(const LoopState& ls, const Eigen::MatrixXd& AinvGt, const Eigen::VectorXd& r,
                                  Eigen::VectorXd& out) {
  S_.noalias() = ls.G * AinvGt;
  rank_ = leastNorm(cod_, S_, kLoopRankTol, r, lambda_);
  out.noalias() = AinvGt * lambda_;
}

void LoopMeter::record(const double* q, const double* u, LoopStats& s) {
  formKinematics(m_, q, u, ws_);
  formLoops(m_, ws_, u, loops_);
  recordViolation(loops_, s);
}

void recordViolation(const LoopState& ls, LoopStats& s) {
  s.position_m = std::max(s.position_m, ls.position_m);
  s.position_rad = std::max(s.position_rad, ls.position_rad);
  s.velocity_m = std::max(s.velocity_m, ls.velocity_m);
  s.velocity_rad = std::max(s.velocity_rad, ls.velocity_rad);
}

LoopProjector::LoopProjector(const Model& m)
    : loops_(m), solve_(m), llt_(m.nu), AinvGt_(m.nu, m.loop_rows), dv_(m.nu), dq_(m.nq) {}

LoopProjector::Result LoopProjector::positions(const Model& m, Workspace& ws, double* q, const double* u, double tol,
                                               int iterations) {
  Result r;
  for (;;) {
    formKinematics(m, q, u, ws);
    formLoops(m, ws, u, loops_);
    formSubtrees(m, ws);
    formA(m, ws);
    llt_.compute(ws.A);
    AinvGt_.noalias() = llt_.solve(loops_.G.transpose());
    // The true gap: g's direction rows also vanish at turns that are not the closure's (formLoops' turn).
    const double gap = std::max(loops_.position_m, loops_.position_rad);
    if (gap <= tol) {
      r.converged = true;
      return r;
    }
    if (!std::isfinite(gap)) {
      r.finite = false;
      return r;
    }
    if (r.iterations == iterations) return r;
    // dv = -A^-1 G^T (G A^-1 G^T)^+ g, q <- q + qdot(q, dv) (eq. (M8)).
    solve_.correction(loops_, AinvGt_, loops_.g, dv_);
    dv_ = -dv_;
    formQdot(m, q, dv_.data(), dq_.data());
    Eigen::Map<Eigen::VectorXd>(q, m.nq) += dq_;
    normalizeQuaternions(m, q);
    ++r.iterations;
  }
}

void LoopProjector::velocities(double* u) {
  solve_.correction(loops_, AinvGt_, loops_.Gu, dv_);  // eq. (M9)
  Eigen::Map<Eigen::VectorXd>(u, dv_.size()) -= dv_;
}

CoordinatePartition::CoordinatePartition(const Model& m)
    : Gd_(m.loop_rows, m.nu), qr_(m.loop_rows, m.nu), qr_d_(m.loop_rows, m.nu), step_(m.nu), dv_(m.nu), dq_(m.nq) {
  dependent_.reserve(m.nu);
  qr_.setThreshold(kLoopRankTol);
  qr_d_.setThreshold(kLoopRankTol);
}

namespace {
// The smallest pivot of a column-pivoted QR's first r, relative to its largest: 0 for r = 0.
double pivotRatio(const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr, int r) {
  if (r <= 0) return 1.0;
  const double first = std::abs(qr.matrixQR()(0, 0));
  return first > 0 ? std::abs(qr.matrixQR()(r - 1, r - 1)) / first : 0.0;
}
}  // namespace

int CoordinatePartition::choose(const LoopState& ls) {
  qr_.compute(ls.G);
  rank_ = static_cast<int>(qr_.rank());
  dependent_.assign(qr_.colsPermutation().indices().data(), qr_.colsPermutation().indices().data() + rank_);
  std::sort(dependent_.begin(), dependent_.end());
  best_ratio_ = pivotRatio(qr_, rank_);
  formGd(ls);
  return rank_;
}

void CoordinatePartition::formGd(const LoopState& ls) {
  Gd_.resize(ls.G.rows(), static_cast<Eigen::Index>(dependent_.size()));  // the same size while the partition holds: no allocation
  for (size_t k = 0; k < dependent_.size(); ++k) Gd_.col(static_cast<Eigen::Index>(k)) = ls.G.col(dependent_[k]);
  qr_d_.compute(Gd_);
}

bool CoordinatePartition::degraded(const LoopState& ls) {
  qr_.compute(ls.G);
  best_ratio_ = pivotRatio(qr_, static_cast<int>(qr_.rank()));
  if (static_cast<int>(qr_.rank()) != rank_) return true;
  formGd(ls);
  best_ratio_ = pivotRatio(qr_, rank_);
  return pivotRatio(qr_d_, rank_) * kRepartitionRatio < best_ratio_;
}

LoopProjector::Result CoordinatePartition::dependent(const Model& m, Workspace& ws, LoopState& ls, double* q, double* u,
                                                     double tol, int iterations) {
  LoopProjector::Result r;
  for (;;) {
    formKinematics(m, q, u, ws);
    formLoops(m, ws, u, ls);
    formGd(ls);
    const double gap = std::max(ls.position_m, ls.position_rad);
    if (!std::isfinite(gap)) {
      r.finite = false;
      return r;
    }
    if (gap <= tol || r.iterations == iterations) {
      r.converged = gap <= tol;
      break;
    }
    // G_d dv_d = -g (least squares on redundant rows), dv_i = 0; q <- q + qdot(q, dv) (eq. (M12)).
    step_.head(rank_) = qr_d_.solve(ls.g);
    dv_.setZero();
    for (int k = 0; k < rank_; ++k) dv_[dependent_[k]] = -step_[k];
    formQdot(m, q, dv_.data(), dq_.data());
    Eigen::Map<Eigen::VectorXd>(q, m.nq) += dq_;
    normalizeQuaternions(m, q);
    ++r.iterations;
  }
  // u_d -= G_d^+ (G u): then G u = 0 with u_i untouched.
  step_.head(rank_) = qr_d_.solve(ls.Gu);
  for (int k = 0; k < rank_; ++k) u[dependent_[k]] -= step_[k];
  return r;
}

ConstrainedEquations constrainedAt(const Model& m, const Workspace& ws, const double* u) {
  ConstrainedEquations out(m);
  formLoops(m, ws, u, out.loops);
  const Eigen::LLT<Eigen::MatrixXd> llt(ws.A);
  if (llt.info() != Eigen::Success) throw std::runtime_error("mass matrix A is not positive definite");
  out.udot = llt.solve(ws.B);
  if (m.loop_rows == 0) return out;  // a tree with point springs or drives: no multipliers (Eigen's 0-column solves bind null references)
  const Eigen::MatrixXd AinvGt = llt.solve(out.loops.G.transpose());
  ConstrainedSolve solve(m);
  out.rank = solve.solve(out.loops, AinvGt, 0.0, 0.0, out.udot);
  out.lambda = solve.lambda();
  return out;
}

void recordLoopSamples(const Model& m, Trajectory& tr) {
  tr.loop_samples.clear();
  tr.lambda_names.clear();
  if (m.loops.empty()) return;
  for (const Loop& l : m.loops)
    for (int r = 0; r < loopRow(l.type).equations; ++r) tr.lambda_names.push_back("lambda." + l.name + "." + std::to_string(r));
  const std::vector<int> pq = m.qFilePermutation(), pu = m.uFilePermutation();
  Eigen::VectorXd q(m.nq), u(m.nu);
  Workspace ws(m);
  for (size_t s = 0; s < tr.size(); ++s) {
    for (int k = 0; k < m.nq; ++k) q[pq[k]] = tr.q[s][k];
    for (int k = 0; k < m.nu; ++k) u[pu[k]] = tr.u[s][k];
    formEquations(m, q.data(), u.data(), ws);
    LoopSample ls;
    try {
      const ConstrainedEquations e = constrainedAt(m, ws, u.data());
      ls = {e.loops.position_m, e.loops.position_rad, e.loops.velocity_m, e.loops.velocity_rad, e.lambda};
    } catch (const std::runtime_error&) {  // A not positive definite at a failed run's last state
      LoopState g(m);
      formLoops(m, ws, u.data(), g);
      ls = {g.position_m, g.position_rad, g.velocity_m, g.velocity_rad,
            Eigen::VectorXd::Constant(m.loop_rows, std::numeric_limits<double>::quiet_NaN())};
    }
    tr.loop_samples.push_back(std::move(ls));
  }
}

void finishMechanism(Model& m) {
  bool welds = false;
  for (const Loop& l : m.loops) welds = welds || l.type == LoopType::Weld;
  if (!welds) return;
  Workspace ws(m);
  const Eigen::VectorXd q = m.q0(), u = Eigen::VectorXd::Zero(m.nu);
  formKinematics(m, q.data(), u.data(), ws);
  for (Loop& l : m.loops)
    if (l.type == LoopType::Weld) l.rel = rotationOf(ws, l.a.body).transpose() * rotationOf(ws, l.b.body);
}

Assembly assembleStart(Model& m, double tol, int iterations) {
  Assembly a;
  Eigen::VectorXd q = m.q0(), u = m.u0();
  const Eigen::VectorXd q0 = q, u0 = u;
  Workspace ws(m);
  formKinematics(m, q.data(), u.data(), ws);
  LoopState before(m);
  formLoops(m, ws, u.data(), before);
  a.gap = before.g.size() ? before.g.cwiseAbs().maxCoeff() : 0.0;
  LoopProjector project(m);
  const LoopProjector::Result r = project.positions(m, ws, q.data(), u.data(), tol, iterations);
  a.iterations = r.iterations;
  a.converged = r.converged && r.finite;
  if (!a.converged) return a;
  a.velocity_gap = before.Gu.size() ? before.Gu.cwiseAbs().maxCoeff() : 0.0;
  project.velocities(u.data());
  a.moved_q = (q - q0).cwiseAbs().maxCoeff();
  a.moved_u = (u - u0).cwiseAbs().maxCoeff();
  for (Body& b : m.bodies) {
    b.joint.q0 = q.segment(b.iq, b.nq());
    b.joint.u0 = u.segment(b.iu, b.nu());
  }
  return a;
}

LoopGap openLoop(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u, double tol) {
  Workspace ws(m);
  formKinematics(m, q.data(), u.data(), ws);
  LoopState ls(m);
  formLoops(m, ws, u.data(), ls);
  int r = 0;
  for (size_t i = 0; i < m.loops.size(); ++i) {
    const Loop& l = m.loops[i];
    const int rows = loopRow(l.type).equations;
    const auto worst = [&](const Eigen::VectorXd& v, int from, int n) { return n > 0 ? v.segment(from, n).cwiseAbs().maxCoeff() : 0.0; };
    const std::string what = "loop '" + l.name + "' ";
    const int L = static_cast<int>(i);
    if (const double e = worst(ls.g, r, 3); e > tol) return {L, what + "is open by " + gnum(e, 3) + " m"};
    if (const double e = ls.turn[i]; e > tol) return {L, what + "is open by " + gnum(e, 3) + " rad"};
    if (const double e = worst(ls.Gu, r, 3); e > tol) return {L, what + "separates at " + gnum(e, 3) + " m/s"};
    if (const double e = worst(ls.Gu, r + 3, rows - 3); e > tol) return {L, what + "turns apart at " + gnum(e, 3) + " rad/s"};
    r += rows;
  }
  return {};
}

}  // namespace em
