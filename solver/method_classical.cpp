// The classical method (paper method a; docs/theory.md §8): u' from A u' = B
// by a Cholesky factorization of A at every evaluation.
#include "solver/method.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

class Classical final : public MethodImpl {
 public:
  Classical(const Model& m, const MethodOptions& opt) : opt_(opt), llt_(m.nu) {}

  Status rates(double t, const double*, const double*, const Workspace& ws, const double*, double* udot, double*, EvalInfo&) override {
    llt_.compute(ws.A);
    if (llt_.info() != Eigen::Success) return Status::failure(t, Failure::NotPositiveDefinite, "mass matrix A not positive definite (Cholesky failed)");
    // A nearly singular A (a gimbal at +-90 deg) factors with a tiny positive
    // pivot and gives garbage: cond(A) >= max L_ii^2 / min L_ii^2 catches it.
    const auto pivots = llt_.matrixLLT().diagonal().cwiseAbs2();
    if (pivots.maxCoeff() > opt_.max_pivot_ratio * pivots.minCoeff())
      return Status::failure(t, Failure::Singular, "mass matrix A numerically singular: cond(A) >= " +
                                    gnum(pivots.maxCoeff() / pivots.minCoeff()) +
                                    " > 1/eps (gimbal lock or extreme mass ratios)");
    Eigen::Map<Eigen::VectorXd> u_dot(udot, ws.B.size());
    u_dot = ws.B;
    llt_.solveInPlace(u_dot);  // paper eq. (1)
    return {};
  }

  bool solveWithA(const double*, const Eigen::MatrixXd& X, Eigen::MatrixXd& out) override {
    out = llt_.solve(X);
    return true;
  }

  // A = L L^T, so M = L^-T has M M^T = A^-1.
  bool inverseSquareRoot(const double*, Eigen::MatrixXd& M) override {
    M.setIdentity();
    llt_.matrixU().solveInPlace(M);
    return true;
  }

 private:
  MethodOptions opt_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace

std::unique_ptr<MethodImpl> makeClassical(const Model& m, const MethodInfo&, const MethodOptions& opt) {
  return std::make_unique<Classical>(m, opt);
}

}  // namespace em
