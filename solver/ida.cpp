// SUNDIALS IDA on the GGL index-2 form (docs/theory.md §15, eqs. (M10)),
// through DaeSolver (solver/dae.hpp).
#include "solver/ida.hpp"

#include <cmath>

#include <Eigen/QR>

#include "solver/applied_forces.hpp"
#include "solver/mechanism/constrained.hpp"

namespace em {

struct IdaRun::Impl {
  const Model& m;
  int nq, nu, r = 0;       // r: the independent loop rows
  bool dampers;
  std::vector<int> rows;   // which rows of G
  Workspace ws;
  LoopState ls;
  Eigen::MatrixXd Gr;      // (r x nu)
  Eigen::VectorXd v, qdot; // (nu), (nq) scratch

  explicit Impl(const Model& model)
      : m(model), nq(model.nq), nu(model.nu), dampers(model.has_dampers), ws(model), ls(model), v(model.nu), qdot(model.nq) {}
  int size() const { return nq + nu + 2 * r + (dampers ? 1 : 0); }

  // g, G (the selected rows) and A, B at (q, u).
  void form(const double* q, const double* u) {
    formEquations(m, q, u, ws);
    formLoops(m, ws, u, ls);
    for (int i = 0; i < r; ++i) Gr.row(i) = ls.G.row(rows[i]);
  }

  // F(t, Y, Y') of eqs. (M10); false where it is not finite.
  bool residual(const double* Y, const double* Yp, double* F) {
    const double* q = Y;
    const double* u = Y + nq;
    Eigen::Map<const Eigen::VectorXd> lambda(Y + nq + nu, r), mu(Y + nq + nu + r, r);
    form(q, u);
    v = Eigen::Map<const Eigen::VectorXd>(u, nu);
    v.noalias() -= Gr.transpose() * mu;
    formQdot(m, q, v.data(), qdot.data());
    Eigen::Map<Eigen::VectorXd>(F, nq) = Eigen::Map<const Eigen::VectorXd>(Yp, nq) - qdot;
    Eigen::Map<Eigen::VectorXd> Fu(F + nq, nu);
    Fu.noalias() = ws.A * Eigen::Map<const Eigen::VectorXd>(Yp + nq, nu);
    Fu -= ws.B;
    Fu.noalias() -= Gr.transpose() * lambda;
    Eigen::Map<Eigen::VectorXd>(F + nq + nu, r).noalias() = Gr * Eigen::Map<const Eigen::VectorXd>(u, nu);
    for (int i = 0; i < r; ++i) F[nq + nu + r + i] = ls.g[rows[i]];
    if (dampers) F[size() - 1] = Yp[size() - 1] - nonConservativePower(m, ws, u);
    return Eigen::Map<const Eigen::VectorXd>(F, size()).allFinite();
  }
};

namespace {

// The rows of G(q0) that are independent: column-pivoted QR of G^T.
std::vector<int> independentRows(const Eigen::MatrixXd& G) {
  if (G.rows() == 0) return {};
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(G.transpose());
  qr.setThreshold(kLoopRankTol);
  std::vector<int> rows;
  for (int k = 0; k < qr.rank(); ++k) rows.push_back(qr.colsPermutation().indices()[k]);
  return rows;
}

}  // namespace

IdaRun::IdaRun(const Model& m, double tol, double max_step, double t_stop) : impl_(std::make_unique<Impl>(m)) {
  Impl& s = *impl_;
  const Eigen::VectorXd q0 = m.q0(), u0 = m.u0();
  formKinematics(m, q0.data(), u0.data(), s.ws);
  formLoops(m, s.ws, u0.data(), s.ls);
  s.rows = independentRows(s.ls.G);
  s.r = rank_ = static_cast<int>(s.rows.size());
  s.Gr.resize(s.r, m.nu);
  s.form(q0.data(), u0.data());
  // Consistent start: u'(0) and lambda(0) from the constrained equations (M7)
  // on the selected rows (full rank); mu = 0; q' = qdot(q, u).
  const Eigen::LLT<Eigen::MatrixXd> llt(s.ws.A);
  const Eigen::VectorXd a = llt.solve(s.ws.B);
  // No rows (a tree with point springs or drives, A05): no multipliers; Eigen's
  // solves with 0 columns bind null references (UBSan).
  const Eigen::MatrixXd AinvGt = s.r ? Eigen::MatrixXd(llt.solve(s.Gr.transpose())) : Eigen::MatrixXd::Zero(m.nu, 0);
  Eigen::VectorXd c(s.r);
  for (int i = 0; i < s.r; ++i) c[i] = s.ls.c[s.rows[i]];
  const Eigen::VectorXd lambda = s.r ? Eigen::VectorXd((s.Gr * AinvGt).ldlt().solve(-c - s.Gr * a)) : Eigen::VectorXd();
  const int n = s.size();
  Eigen::VectorXd Y = Eigen::VectorXd::Zero(n), Yp = Eigen::VectorXd::Zero(n);
  Y.head(m.nq) = q0;
  Y.segment(m.nq, m.nu) = u0;
  Y.segment(m.nq + m.nu, s.r) = lambda;
  formQdot(m, q0.data(), u0.data(), Yp.data());
  Yp.segment(m.nq, m.nu) = a + AinvGt * lambda;
  if (s.dampers) Yp[n - 1] = nonConservativePower(m, s.ws, u0.data());
  std::vector<bool> differential(n, true);
  for (int i = m.nq + m.nu; i < m.nq + m.nu + 2 * s.r; ++i) differential[i] = false;  // lambda, mu
  dae_ = std::make_unique<DaeSolver>(
      n, [&s](double, const double* y, const double* yp, double* F) { return s.residual(y, yp, F); }, differential, Y.data(),
      Yp.data(), tol, max_step, t_stop);
}

IdaRun::~IdaRun() = default;

Status IdaRun::advance(double t_out) {
  if (dae_->advance(t_out)) return {};
  return Status::failure(dae_->t(), Failure::IntegratorStopped, "IDA stopped: " + dae_->error());
}

void IdaRun::state(double* y) const {
  const Impl& s = *impl_;
  const double* Y = dae_->y();
  for (int i = 0; i < s.nq + s.nu; ++i) y[i] = Y[i];
  if (s.dampers) y[s.nq + s.nu] = Y[s.size() - 1];
}

long IdaRun::steps() const { return dae_->steps(); }
long IdaRun::residualEvaluations() const { return dae_->residualEvaluations(); }

}  // namespace em
