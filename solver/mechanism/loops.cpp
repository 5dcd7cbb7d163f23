// The closures at one state (docs/theory.md §15): every loop's rows by its kind.
#include "solver/mechanism/loops.hpp"

#include <algorithm>

#include "solver/formation.hpp"
#include "solver/mechanism/loop_rows.hpp"
#include "solver/text.hpp"

namespace em {

LoopState::LoopState(const Model& m)
    : g(Eigen::VectorXd::Zero(m.loop_rows)), Gu(Eigen::VectorXd::Zero(m.loop_rows)), c(Eigen::VectorXd::Zero(m.loop_rows)),
      G(Eigen::MatrixXd::Zero(m.loop_rows, m.nu)), Jw(3, m.nu), turn(m.loops.size(), 0.0) {}

namespace {

// The largest |v| over rows [from, from + n), 0 for none.
double worst(const Eigen::VectorXd& v, int from, int n) { return n > 0 ? v.segment(from, n).cwiseAbs().maxCoeff() : 0.0; }

}  // namespace

void addLoopGramian(const Model& m, const Eigen::MatrixXd& G, double scale, Eigen::MatrixXd& M) {
  int r = 0;
  for (size_t i = 0; i < m.loops.size(); ++i) {
    const int rows = loopRow(m.loops[i].type).equations;
    for (int a : m.loop_speeds[i])
      for (int b : m.loop_speeds[i]) M(a, b) += scale * G.col(a).segment(r, rows).dot(G.col(b).segment(r, rows));
    r += rows;
  }
}

void formLoops(const Model& m, const Workspace& ws, const double* u, LoopState& ls) {
  // G's rows touch only their loop's speeds (Model::loop_speeds): those are
  // cleared and summed, never the rest, which stays zero (O(rows x depth), not O(rows x nu)).
  int r = 0;
  for (size_t i = 0; i < m.loops.size(); ++i) {
    const LoopTypeInfo& kind = loopRow(m.loops[i].type);
    for (int j : m.loop_speeds[i]) ls.G.col(j).segment(r, kind.equations).setZero();
    ls.turn[i] = kind.equations_of->form({m, ws, u, m.loops[i], m.loop_speeds[i]}, r, ls);
    for (int k = r; k < r + kind.equations; ++k) {
      double gu = 0;
      for (int j : m.loop_speeds[i]) gu += ls.G(k, j) * u[j];
      ls.Gu[k] = gu;
    }
    r += kind.equations;
  }
  ls.position_m = ls.position_rad = ls.velocity_m = ls.velocity_rad = 0;
  r = 0;
  for (size_t i = 0; i < m.loops.size(); ++i) {
    const LoopTypeInfo& kind = loopRow(m.loops[i].type);
    const int np = kind.point_rows, nd = kind.equations - kind.point_rows;
    ls.position_m = std::max(ls.position_m, worst(ls.g, r, np));
    ls.velocity_m = std::max(ls.velocity_m, worst(ls.Gu, r, np));
    ls.position_rad = std::max(ls.position_rad, ls.turn[i]);
    ls.velocity_rad = std::max(ls.velocity_rad, worst(ls.Gu, r + np, nd));
    r += kind.equations;
  }
}

double loopPointGap(const Loop& l, const Vec3& xa, const Vec3& xb, const Mat3& Ra) {
  return loopRow(l.type).equations_of->gap(l, xa, xb, Ra);
}

void recordViolation(const LoopState& ls, LoopStats& s) {
  s.position_m = std::max(s.position_m, ls.position_m);
  s.position_rad = std::max(s.position_rad, ls.position_rad);
  s.velocity_m = std::max(s.velocity_m, ls.velocity_m);
  s.velocity_rad = std::max(s.velocity_rad, ls.velocity_rad);
}

void LoopMeter::record(const double* q, const double* u, LoopStats& s) {
  formKinematics(m_, q, u, ws_);
  formLoops(m_, ws_, u, loops_);
  recordViolation(loops_, s);
}

LoopGap openLoop(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u, double tol) {
  Workspace ws(m);
  formKinematics(m, q.data(), u.data(), ws);
  LoopState ls(m);
  formLoops(m, ws, u.data(), ls);
  int r = 0;
  for (size_t i = 0; i < m.loops.size(); ++i) {
    const Loop& l = m.loops[i];
    const LoopTypeInfo& kind = loopRow(l.type);
    const int np = kind.point_rows, nd = kind.equations - kind.point_rows;
    const std::string what = "loop '" + l.name + "' ";
    const int L = static_cast<int>(i);
    if (const double e = worst(ls.g, r, np); e > tol) return {L, what + "is open by " + gnum(e, 3) + " m"};
    if (const double e = ls.turn[i]; e > tol) return {L, what + "is open by " + gnum(e, 3) + " rad"};
    if (const double e = worst(ls.Gu, r, np); e > tol) return {L, what + "separates at " + gnum(e, 3) + " m/s"};
    if (const double e = worst(ls.Gu, r + np, nd); e > tol) return {L, what + "turns apart at " + gnum(e, 3) + " rad/s"};
    r += kind.equations;
  }
  return {};
}

}  // namespace em
