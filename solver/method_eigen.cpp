// The Junkins–Schaub eigenfactor methods (paper methods b and c; docs/theory.md
// §7–8): C and lambda integrated beside (q, u), u' = C^T Lambda^-1 C B, and
// the registry row's correction after every accepted step.
#include "solver/method.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

class EigenMethod final : public MethodImpl {
 public:
  EigenMethod(const Model& m, const MethodInfo& row, const MethodOptions& opt)
      : N_(m.nu), correction_(row.correction), refine_(static_cast<int>(row.param("refine", opt))),
        refine_tol_(row.param("refine_tol", opt)), opt_(opt), corr_(m.nu) {
    Omega_.setZero(N_, N_);
    AdotCt_.setZero(N_, N_);
    z_.setZero(N_);
    r_.setZero(N_);
    du_.setZero(N_);
  }

  bool needsAdot() const override { return true; }
  bool needsA() const override { return refine_ > 0; }
  bool correctsAfterStep() const override { return correction_ != Correction::None; }
  bool hasDiagnostics() const override { return true; }

  // x = [C (N*N, row-major), lambda (N)] (ExtraState::CLambda).
  void initialize(const Workspace& ws, double* x) override {
    startFromEigensolver(ws.A, Eigen::Map<RowMatrix>(x, N_, N_), Eigen::Map<Eigen::VectorXd>(x + N_ * N_, N_));
  }

  Status rates(double t, const double*, const double*, const Workspace& ws, const double* x, double* udot, double* xdot, EvalInfo& info) override {
    Eigen::Map<const RowMatrix> C(x, N_, N_);
    Eigen::Map<const Eigen::VectorXd> lambda(x + N_ * N_, N_);
    Eigen::Map<RowMatrix> Cdot(xdot, N_, N_);
    Eigen::Map<Eigen::VectorXd> lambda_dot(xdot + N_ * N_, N_);
    // Hazards the harness must report, not hide (docs/theory.md §7).
    const double lmax = lambda.maxCoeff();
    for (int i = 0; i < N_; ++i)
      if (!(lambda[i] > 0))
        return Status::failure(t, Failure::NonPositiveEigenvalue, "eigenvalue lambda_" + std::to_string(i) + " = " + gnum(lambda[i]) + " <= 0");
    const double floor = opt_.gap_floor_rel * lmax;
    const RateStatus st = eigenRates(C, lambda, ws.Adot, floor, Omega_, AdotCt_, lambda_dot, Cdot);
    if (!st.ok)
      return Status::failure(t, Failure::EigenGap, "eigenvalue gap |lambda_" + std::to_string(st.i) + " - lambda_" + std::to_string(st.j) +
                                    "| = " + gnum(st.gap) + " below the floor " + gnum(floor));
    info.max_Omega = st.max_Omega;
    // u' = H B with H = C^T Lambda^-1 C (paper eq. (17)), then refine_ residual corrections.
    const auto applyH = [&](const Eigen::VectorXd& b, Eigen::Ref<Eigen::VectorXd> out) {
      z_.noalias() = C * b;
      z_.array() /= lambda.array();
      out.noalias() = C.transpose() * z_;
    };
    return solveByEigenfactors(t, ws, refine_, refine_tol_, applyH, Eigen::Map<Eigen::VectorXd>(udot, N_), r_, du_);
  }

  // A^-1 X = C^T Lambda^-1 C X (paper eq. (17)): the multipliers of a
  // mechanism through the eigenfactors, A^(-1/2) = C^T Lambda^(-1/2) C.
  bool hasOwnInverse() const override { return true; }
  bool solveWithA(const double* x, const Eigen::MatrixXd& X, Eigen::MatrixXd& out) override {
    Eigen::Map<const RowMatrix> C(x, N_, N_);
    Eigen::Map<const Eigen::VectorXd> lambda(x + N_ * N_, N_);
    CX_.resize(N_, X.cols());
    CX_.noalias() = C * X;
    CX_.array().colwise() /= lambda.array();
    out.noalias() = C.transpose() * CX_;
    return true;
  }

  // The paper's parameterization carried to mechanisms: M = C^T Lambda^(-1/2)
  // has M M^T = C^T Lambda^-1 C = A^-1 (eq. (17)), with no factorization.
  bool inverseSquareRoot(const double* x, Eigen::MatrixXd& M) override {
    Eigen::Map<const RowMatrix> C(x, N_, N_);
    Eigen::Map<const Eigen::VectorXd> lambda(x + N_ * N_, N_);
    M.noalias() = C.transpose() * lambda.cwiseSqrt().cwiseInverse().asDiagonal();
    return true;
  }

  Status afterStep(double t, const Workspace& ws, double* x, StepInfo& info) override {
    Eigen::Map<RowMatrix> C(x, N_, N_);
    Eigen::Map<Eigen::VectorXd> lambda(x + N_ * N_, N_);
    if (correction_ == Correction::OrthonormalizeJacobi) symmetricOrthonormalize(C, corr_);
    if (correction_ != Correction::None) {
      const Status s = jacobiCorrectAt(t, ws.A, C, lambda, corr_, opt_, info);
      if (!s) return s;
    }
    info.min_gap = minEigenGap(lambda);
    return {};
  }

  EigenDiagnostics diagnostics(const Workspace& ws, const double* x, double max_Omega) const override {
    return eigenDiagnostics(ws.A, Eigen::Map<const RowMatrix>(x, N_, N_),
                            Eigen::Map<const Eigen::VectorXd>(x + N_ * N_, N_), max_Omega);
  }

 private:
  int N_;
  Correction correction_;
  int refine_;  // residual corrections per evaluation (the row's option "refine")
  double refine_tol_;  // relative residual the last correction must reach (the row's option "refine_tol")
  MethodOptions opt_;
  Eigen::MatrixXd Omega_, AdotCt_;  // (N x N) scratch: Omega (G formed in place) and A' C^T
  Eigen::VectorXd z_;               // (N) scratch: Lambda^-1 C b
  Eigen::MatrixXd CX_;              // (N x m) scratch: Lambda^-1 C X for a mechanism's multipliers
  Eigen::VectorXd r_, du_;          // (N) scratch of refineResidual
  CorrectionScratch corr_;
};

}  // namespace

std::unique_ptr<MethodImpl> makeEigen(const Model& m, const MethodInfo& row, const MethodOptions& opt) {
  return std::make_unique<EigenMethod>(m, row, opt);
}

}  // namespace em
