#include "solver/method.hpp"

#include "solver/text.hpp"

namespace em {

Status MethodImpl::afterStep(double, const Workspace&, double*, StepInfo&) { return {}; }

EigenDiagnostics MethodImpl::diagnostics(const Workspace&, const double*, double) const { return {}; }

void startFromEigensolver(const Eigen::MatrixXd& A, Eigen::Ref<RowMatrix> C, Eigen::Ref<Eigen::VectorXd> lambda) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  C = es.eigenvectors().transpose();
  lambda = es.eigenvalues();
}

Status jacobiCorrectAt(double t, const Eigen::MatrixXd& A, Eigen::Ref<RowMatrix> C, Eigen::Ref<Eigen::VectorXd> lambda,
                       CorrectionScratch& w, const MethodOptions& opt, StepInfo& info) {
  info.corrected = true;
  info.jacobi = jacobiCorrect(A, C, lambda, w, opt.jacobi_tol, opt.jacobi_max_sweeps);
  if (info.jacobi.converged) return {};
  const double orth = (C * C.transpose() - Eigen::MatrixXd::Identity(C.rows(), C.cols())).norm();
  return Status::failure(t, Failure::JacobiNotConverged,
                         "Jacobi correction did not converge in " + std::to_string(opt.jacobi_max_sweeps) +
                             " sweeps (off(C A C^T)/||A|| = " + gnum(offDiagonalNorm(w.work) / A.norm()) +
                             ", ||C C^T - I|| = " + gnum(orth) + ")");
}

}  // namespace em
