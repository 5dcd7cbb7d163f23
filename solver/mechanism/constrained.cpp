// The constrained accelerations of a mechanism (docs/theory.md §15).
#include "solver/mechanism/constrained.hpp"

#include <limits>
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

}  // namespace em
