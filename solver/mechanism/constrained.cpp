// The constrained accelerations of a mechanism (docs/theory.md §15).
#include "solver/mechanism/constrained.hpp"

#include <algorithm>
#include <iterator>
#include <limits>
#include <memory>
#include <stdexcept>

#include "solver/formation.hpp"

namespace em {

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

// The speeds both sorted lists hold.
std::vector<int> shared(const std::vector<int>& a, const std::vector<int>& b) {
  std::vector<int> out;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

}  // namespace

ConstrainedSolve::ConstrainedSolve(const Model& m)
    : m_(m), S_(m.loop_rows, m.loop_rows), GM_(m.loop_rows, m.nu), r_(m.loop_rows), lambda_(Eigen::VectorXd::Zero(m.loop_rows)),
      w_(m.nu), Ga_(m.loop_rows), cod_(m.loop_rows, m.loop_rows), cod_gm_(m.loop_rows, m.nu), first_(m.loop_rows, 0),
      Y_(Eigen::MatrixXd::Zero(m.nu, m.loop_rows)), E_(Eigen::MatrixXd::Zero(m.loop_rows, m.loop_rows)), d_(m.loop_rows),
      v_(m.nu) {
  const int L = static_cast<int>(m.loops.size());
  for (int l = 0; l < L; ++l) {
    loop_row_.push_back(static_cast<int>(row_loop_.size()));
    row_loop_.insert(row_loop_.end(), loopRow(m.loops[l].type).equations, l);
  }
  for (int r = 0; r < m.loop_rows; ++r) first_[r] = loop_row_[row_loop_[r]];
  for (int a = 0; a < L; ++a)
    for (int b = 0; b <= a; ++b)
      if (std::vector<int> both = shared(m.loop_speeds[a], m.loop_speeds[b]); !both.empty()) {
        for (int r = loop_row_[a]; r < loop_row_[a] + loopRow(m.loops[a].type).equations; ++r)
          first_[r] = std::min(first_[r], loop_row_[b]);
        pairs_.push_back({a, b, std::move(both)});
      }
}

// r = b - G a, b = -c - 2 alpha G u - beta^2 g: what the constraint force must add to g''.
void ConstrainedSolve::residual(const LoopState& ls, double alpha, double beta) {
  r_ = -ls.c - 2.0 * alpha * ls.Gu - beta * beta * ls.g - Ga_;
}

void ConstrainedSolve::timesG(const LoopState& ls, const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> out) const {
  for (int r = 0; r < m_.loop_rows; ++r) {
    double sum = 0;
    for (int j : m_.loop_speeds[row_loop_[r]]) sum += ls.G(r, j) * x[j];
    out[r] = sum;
  }
}

void ConstrainedSolve::addTimesGt(const LoopState& ls, const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Ref<Eigen::VectorXd> out) const {
  for (int r = 0; r < m_.loop_rows; ++r)
    if (const double vr = v[r]; vr != 0)
      for (int j : m_.loop_speeds[row_loop_[r]]) out[j] += ls.G(r, j) * vr;
}

int ConstrainedSolve::solve(const LoopState& ls, const Eigen::MatrixXd& AinvGt, double alpha, double beta,
                            Eigen::Ref<Eigen::VectorXd> udot) {
  S_.noalias() = ls.G * AinvGt;
  Ga_.noalias() = ls.G * udot;
  residual(ls, alpha, beta);
  rank_ = leastNorm(cod_, S_, kLoopRankTol, r_, lambda_);
  udot.noalias() += AinvGt * lambda_;
  return rank_;
}

int ConstrainedSolve::solveUdwadiaKalaba(const LoopState& ls, const Eigen::MatrixXd& M, double alpha, double beta,
                                         Eigen::Ref<Eigen::VectorXd> udot) {
  GM_.noalias() = ls.G * M;
  Ga_.noalias() = ls.G * udot;
  residual(ls, alpha, beta);
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

void ConstrainedSolve::factorSparse(const LoopState& ls, const TreeCholesky& A, double shift) {
  const int m = m_.loop_rows;
  // Y = L^-T G^T, row by row of G on its loop's speeds (eq. (S2)).
  for (int r = 0; r < m; ++r) {
    const std::vector<int>& speeds = m_.loop_speeds[row_loop_[r]];
    double* y = Y_.col(r).data();
    for (int j : speeds) y[j] = ls.G(r, j);
    A.solveLtOn(speeds, y);
  }
  // G A^-1 G^T = Y^T D^-1 Y, over the pairs of loops that share speeds; the rest of the envelope cleared.
  const Eigen::VectorXd& D = A.pivots();
  for (int r = 0; r < m; ++r) E_.row(r).segment(first_[r], r - first_[r] + 1).setZero();
  for (const SharedSpeeds& p : pairs_) {
    const int ra = loop_row_[p.a], na = loopRow(m_.loops[p.a].type).equations;
    const int rb = loop_row_[p.b], nb = loopRow(m_.loops[p.b].type).equations;
    for (int r = ra; r < ra + na; ++r)
      for (int c = rb; c < rb + nb && c <= r; ++c) {
        double sum = 0;
        for (int i : p.speeds) sum += Y_(i, r) * Y_(i, c) / D[i];
        E_(r, c) = sum;
      }
  }
  // LDL^T over the envelope, in place; a pivot at most kLoopRankTol of the
  // largest diagonal drops its row (redundant: its lambda is 0). Shifted, none drops.
  double largest = 0;
  for (int r = 0; r < m; ++r) largest = std::max(largest, E_(r, r) += shift);
  const double drop = shift > 0 ? 0.0 : kLoopRankTol * largest;
  rank_ = 0;
  for (int r = 0; r < m; ++r) {
    const int f = first_[r];
    for (int c = f; c < r; ++c) {
      if (d_[c] == 0) {
        E_(r, c) = 0;
        continue;
      }
      double v = E_(r, c);
      for (int k = std::max(f, first_[c]); k < c; ++k) v -= E_(r, k) * d_[k] * E_(c, k);
      E_(r, c) = v / d_[c];
    }
    double dr = E_(r, r);
    for (int k = f; k < r; ++k) dr -= E_(r, k) * E_(r, k) * d_[k];
    d_[r] = dr > drop && largest > 0 ? dr : 0.0;
    if (d_[r] > 0) ++rank_;
  }
}

void ConstrainedSolve::solveSparse(const Eigen::VectorXd& r) {
  const int m = m_.loop_rows;
  lambda_ = r;
  for (int i = 0; i < m; ++i)
    for (int c = first_[i]; c < i; ++c) lambda_[i] -= E_(i, c) * lambda_[c];
  for (int i = 0; i < m; ++i) lambda_[i] = d_[i] > 0 ? lambda_[i] / d_[i] : 0.0;
  for (int i = m - 1; i >= 0; --i)
    for (int c = first_[i]; c < i; ++c) lambda_[c] -= E_(i, c) * lambda_[i];
}

void ConstrainedSolve::addInverseAGt(const TreeCholesky& A, double* out) {
  // A^-1 G^T lambda = L^-1 D^-1 (Y lambda) (eq. (S3)).
  v_.setZero();
  for (int r = 0; r < m_.loop_rows; ++r)
    if (const double l = lambda_[r]; l != 0)
      for (int j : m_.loop_speeds[row_loop_[r]]) v_[j] += Y_(j, r) * l;
  v_.array() /= A.pivots().array();
  A.solveL(v_.data());
  Eigen::Map<Eigen::VectorXd>(out, m_.nu) += v_;
}

int ConstrainedSolve::solve(const LoopState& ls, const TreeCholesky& A, double alpha, double beta,
                            Eigen::Ref<Eigen::VectorXd> udot) {
  timesG(ls, udot, Ga_);  // G a on each row's loop speeds
  residual(ls, alpha, beta);
  factorSparse(ls, A);
  solveSparse(r_);
  addInverseAGt(A, udot.data());
  return rank_;
}

void ConstrainedSolve::correction(const LoopState& ls, const TreeCholesky& A, const Eigen::VectorXd& r, Eigen::VectorXd& out) {
  factorSparse(ls, A);
  solveSparse(r);
  out.setZero();
  addInverseAGt(A, out.data());
}

void ConstrainedSolve::factorPenalty(const LoopState& ls, const TreeCholesky& A, double shift) { factorSparse(ls, A, shift); }

void ConstrainedSolve::penaltySolve(const TreeCholesky& A, const Eigen::VectorXd& r, Eigen::VectorXd& out) {
  solveSparse(r);
  out.setZero();
  addInverseAGt(A, out.data());
}

int ConstrainedSolve::rankOf(const LoopState& ls, const TreeCholesky& A) {
  factorSparse(ls, A);
  return rank_;
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
  Eigen::VectorXd q(m.nq), u(m.nu), udot(m.nu);
  Workspace ws(m);
  // Where A's tree-sparse factors pay (docs/theory.md §16) the samples' lambda
  // come from them, at linear cost per sample (the dense path cost a row of
  // 80 four-bars more than its run): the same G^T lambda, 0 on dropped rows.
  std::unique_ptr<TreeCholesky> tree = TreeCholesky::pays(m) ? std::make_unique<TreeCholesky>(m) : nullptr;
  ConstrainedSolve sparse(m);
  LoopState at(m);
  for (size_t s = 0; s < tr.size(); ++s) {
    for (int k = 0; k < m.nq; ++k) q[pq[k]] = tr.q[s][k];
    for (int k = 0; k < m.nu; ++k) u[pu[k]] = tr.u[s][k];
    formEquations(m, q.data(), u.data(), ws);
    LoopSample ls;
    if (tree && tree->factor(ws.A)) {
      formLoops(m, ws, u.data(), at);
      udot = ws.B;
      tree->solveInPlace(udot.data());
      sparse.solve(at, *tree, 0.0, 0.0, udot);
      tr.loop_samples.push_back({at.position_m, at.position_rad, at.velocity_m, at.velocity_rad, sparse.lambda()});
      continue;
    }
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

}  // namespace em
