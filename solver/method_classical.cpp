// The classical method (paper method a; docs/theory.md §8): u' from A u' = B
// by a Cholesky factorization of A at every evaluation: over the tree's own
// sparsity where it pays (TreeCholesky, docs/theory.md §16: a wide, shallow
// tree, a row of four-bars), else dense.
#include "solver/method.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

class Classical final : public MethodImpl {
 public:
  Classical(const Model& m, const MethodOptions& opt)
      : opt_(opt), llt_(m.nu), tree_(TreeCholesky::pays(m) ? std::make_unique<TreeCholesky>(m) : nullptr) {}

  Status rates(double t, const double*, const double*, const Workspace& ws, const double*, double* udot, double*, EvalInfo&) override {
    if (tree_ ? !tree_->factor(ws.A) : (llt_.compute(ws.A), llt_.info() != Eigen::Success))
      return Status::failure(t, Failure::NotPositiveDefinite, "mass matrix A not positive definite (Cholesky failed)");
    // A nearly singular A (a gimbal at +-90 deg) factors with a tiny positive
    // pivot and gives garbage: cond(A) >= max pivot / min pivot catches it.
    const double spread = tree_ ? tree_->pivots().maxCoeff() / tree_->pivots().minCoeff()
                                : llt_.matrixLLT().diagonal().cwiseAbs2().maxCoeff() / llt_.matrixLLT().diagonal().cwiseAbs2().minCoeff();
    if (!(spread <= opt_.max_pivot_ratio))
      return Status::failure(t, Failure::Singular, "mass matrix A numerically singular: cond(A) >= " + gnum(spread) +
                                    " > 1/eps (gimbal lock or extreme mass ratios)");
    Eigen::Map<Eigen::VectorXd> u_dot(udot, ws.B.size());
    u_dot = ws.B;
    if (tree_) tree_->solveInPlace(udot);  // paper eq. (1)
    else llt_.solveInPlace(u_dot);
    return {};
  }

  bool hasOwnInverse() const override { return !tree_; }
  const TreeCholesky* treeFactor() const override { return tree_.get(); }

  bool solveWithA(const double*, const Eigen::MatrixXd& X, Eigen::MatrixXd& out) override {
    if (tree_) return false;  // Dynamics then asks treeFactor()
    out = llt_.solve(X);
    return true;
  }

  // A = L L^T, so M = L^-T has M M^T = A^-1 (the dense factor; with the tree's, Dynamics forms it).
  bool inverseSquareRoot(const double*, Eigen::MatrixXd& M) override {
    if (tree_) return false;
    M.setIdentity();
    llt_.matrixU().solveInPlace(M);
    return true;
  }

 private:
  MethodOptions opt_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  std::unique_ptr<TreeCholesky> tree_;  // null: the tree's pattern does not pay, A is factored densely
};

}  // namespace

std::unique_ptr<MethodImpl> makeClassical(const Model& m, const MethodInfo&, const MethodOptions& opt) {
  return std::make_unique<Classical>(m, opt);
}

}  // namespace em
