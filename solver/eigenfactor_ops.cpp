#include "solver/eigenfactor_ops.hpp"

#include "solver/text.hpp"

#include <cmath>
#include <limits>

namespace em {

double offDiagonalNorm(const Eigen::Ref<const Eigen::MatrixXd>& X) {
  // Summed directly: ||X||^2 - ||diag X||^2 cancels catastrophically near diagonal X.
  double s = 0;
  for (int j = 0; j < X.cols(); ++j)
    for (int i = 0; i < X.rows(); ++i)
      if (i != j) s += X(i, j) * X(i, j);
  return std::sqrt(s);
}

void rotate(Eigen::MatrixXd& X, Eigen::Ref<RowMatrix> C, int p, int q) {
  const double theta = (X(q, q) - X(p, p)) / (2.0 * X(p, q));
  const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
  const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
  const int N = static_cast<int>(X.rows());
  for (int k = 0; k < N; ++k) {  // columns: X J
    const double dp = X(k, p), dq = X(k, q);
    X(k, p) = c * dp - s * dq;
    X(k, q) = s * dp + c * dq;
  }
  for (int k = 0; k < N; ++k) {  // rows: J^T (X J)
    const double dp = X(p, k), dq = X(q, k);
    X(p, k) = c * dp - s * dq;
    X(q, k) = s * dp + c * dq;
  }
  for (int k = 0; k < N; ++k) {  // eigenvector rows
    const double cp = C(p, k), cq = C(q, k);
    C(p, k) = c * cp - s * cq;
    C(q, k) = s * cp + c * cq;
  }
}

JacobiStats jacobiCorrect(const Eigen::MatrixXd& A, Eigen::Ref<RowMatrix> C,
                          Eigen::Ref<Eigen::VectorXd> lambda, CorrectionScratch& w,
                          double tol, int max_sweeps) {
  JacobiStats st;
  const int N = static_cast<int>(A.rows());
  Eigen::MatrixXd& CACt = w.work;  // the Jacobi iterate C A C^T
  w.W.noalias() = A * C.transpose();
  CACt.noalias() = C * w.W;
  const double bound = tol * A.norm();
  while (offDiagonalNorm(CACt) > bound) {
    if (st.sweeps == max_sweeps) { st.converged = false; break; }
    ++st.sweeps;
    for (int p = 0; p < N - 1; ++p)
      for (int q = p + 1; q < N; ++q)
        if (CACt(p, q) != 0.0) { rotate(CACt, C, p, q); ++st.rotations; }
  }
  lambda = CACt.diagonal();
  return st;
}

void symmetricOrthonormalize(Eigen::Ref<RowMatrix> C, CorrectionScratch& w) {
  w.work.noalias() = C * C.transpose();
  w.es.compute(w.work);
  const Eigen::MatrixXd& V = w.es.eigenvectors();
  w.W.noalias() = V * w.es.eigenvalues().cwiseSqrt().cwiseInverse().asDiagonal();
  w.work.noalias() = w.W * V.transpose();
  w.W.noalias() = w.work * C;
  C = w.W;
}

RateStatus eigenRates(const Eigen::Ref<const RowMatrix>& C, const Eigen::Ref<const Eigen::VectorXd>& lambda,
                      const Eigen::MatrixXd& Adot, double gap_floor, Eigen::MatrixXd& Omega, Eigen::MatrixXd& AdotCt,
                      Eigen::Ref<Eigen::VectorXd> lambda_dot, Eigen::Ref<RowMatrix> Cdot) {
  RateStatus st;
  const int N = static_cast<int>(lambda.size());
  AdotCt.noalias() = Adot * C.transpose();
  // G = C A' C^T is symmetric: only its upper half (and diagonal) is formed
  // and read, half of the product's flops. Overwritten by Omega below.
  Omega.triangularView<Eigen::Upper>() = C * AdotCt;
  lambda_dot = Omega.diagonal();
  for (int i = 0; i < N; ++i) {
    Omega(i, i) = 0;
    for (int j = i + 1; j < N; ++j) {
      const double gap = lambda[j] - lambda[i];
      if (!(std::abs(gap) >= gap_floor)) return {false, i, j, std::abs(gap), st.max_Omega};
      // G is symmetric, so Omega_ji = G_ij / (lambda_i - lambda_j) = -Omega_ij: Omega is skew.
      const double w = Omega(i, j) / gap;
      Omega(i, j) = w;
      Omega(j, i) = -w;
      st.max_Omega = std::max(st.max_Omega, std::abs(w));
    }
  }
  Cdot.noalias() = -Omega * C;
  return st;
}

std::string refineDivergedCause(int steps) {
  return "residual correction diverged (r^T H r, r = B - A u', grew within " + std::to_string(steps) +
         " corrections): the eigenfactors H no longer approximate A's inverse";
}

std::string refineNotConvergedCause(int steps, double residual, double tol) {
  return "residual correction not converged: relative residual sqrt(r^T H r / B^T H B) = " + gnum(residual, 3) +
         " after " + std::to_string(steps) + " corrections, beyond refine_tol " + gnum(tol, 3) +
         ": u' is not classical's; more corrections (--refine) or a Jacobi correction";
}

double minEigenGap(const Eigen::Ref<const Eigen::VectorXd>& lambda) {
  double g = std::numeric_limits<double>::infinity();
  for (int i = 0; i < lambda.size(); ++i)
    for (int j = i + 1; j < lambda.size(); ++j) g = std::min(g, std::abs(lambda[i] - lambda[j]));
  return g;
}

EigenDiagnostics eigenDiagnostics(const Eigen::MatrixXd& A, const Eigen::Ref<const RowMatrix>& C,
                                  const Eigen::Ref<const Eigen::VectorXd>& lambda, double max_Omega) {
  const int N = static_cast<int>(A.rows());
  EigenDiagnostics d;
  d.orth_err = (C * C.transpose() - Eigen::MatrixXd::Identity(N, N)).norm();
  d.offdiag_rel = offDiagonalNorm(C * A * C.transpose()) / A.norm();
  d.min_gap = minEigenGap(lambda);
  d.max_Omega = max_Omega;
  const Eigen::MatrixXd Ainv = A.llt().solve(Eigen::MatrixXd::Identity(N, N));
  const Eigen::MatrixXd Ainv_eig = C.transpose() * lambda.cwiseInverse().asDiagonal() * C;
  d.inv_err = (Ainv_eig - Ainv).norm() / Ainv.norm();
  return d;
}

}  // namespace em
