// A = L^T D L over the tree's sparsity (docs/theory.md §16, eq. (S1)).
#include "solver/tree_cholesky.hpp"

namespace em {

namespace {
// The share of a dense triangle below which the tree's pattern pays (TreeCholesky::pays).
constexpr double kSparseShare = 0.25;
}  // namespace

std::vector<int> speedParents(const Model& m) {
  std::vector<int> parent(m.nu, -1);
  for (int k = 0; k < m.n(); ++k) {
    const int iu = m.body_iu[k];
    for (int j = 1; j < m.body_nu[k]; ++j) parent[iu + j] = iu + j - 1;
    if (m.body_nu[k] == 0) continue;
    int p = m.body_parent[k];
    while (p >= 0 && m.body_nu[p] == 0) p = m.body_parent[p];
    parent[iu] = p < 0 ? -1 : m.body_iu[p] + m.body_nu[p] - 1;
  }
  return parent;
}

TreeCholesky::TreeCholesky(const Model& m) : parent_(speedParents(m)), start_(m.nu + 1, 0), D_(m.nu) {
  for (int i = 0; i < m.nu; ++i) {
    start_[i] = static_cast<int>(anc_.size());
    for (int j = parent_[i]; j >= 0; j = parent_[j]) anc_.push_back(j);
  }
  start_[m.nu] = static_cast<int>(anc_.size());
  L_.assign(anc_.size(), 0.0);
}

bool TreeCholesky::pays(const Model& m) {
  const std::vector<int> parent = speedParents(m);
  double below = 0;
  for (int i = 0; i < m.nu; ++i)
    for (int j = parent[i]; j >= 0; j = parent[j]) ++below;
  const double dense = 0.5 * m.nu * (m.nu - 1.0);
  return m.nu > 1 && below <= kSparseShare * dense;
}

bool TreeCholesky::factor(const Eigen::MatrixXd& A) {
  const int n = size();
  for (int i = 0; i < n; ++i) {
    D_[i] = A(i, i);
    for (int p = start_[i]; p < start_[i + 1]; ++p) L_[p] = A(anc_[p], i);  // above the diagonal: formA's own entries
  }
  return eliminate();
}

bool TreeCholesky::factor(const Eigen::MatrixXd& A, const Eigen::VectorXd& extra) {
  const int n = size();
  for (int i = 0; i < n; ++i) {
    D_[i] = A(i, i) + extra[i];
    for (int p = start_[i]; p < start_[i + 1]; ++p) L_[p] = A(anc_[p], i);
  }
  return eliminate();
}

bool TreeCholesky::eliminate() {
  const int n = size();
  // Featherstone's LTDL (RBDA Table 6.3): from the leaves up, row k's entries
  // divided by its pivot and its outer product taken from its ancestors' rows.
  // Row i = anc(k)[p]'s ancestors are anc(k)[p+1 ...]: the rows share storage order.
  for (int k = n - 1; k >= 0; --k) {
    const double dk = D_[k];
    if (!(dk > 0)) return false;
    const int s = start_[k], e = start_[k + 1];
    for (int p = s; p < e; ++p) {
      const int i = anc_[p];
      const double a = L_[p] / dk;
      D_[i] -= a * L_[p];
      double* Li = L_.data() + start_[i];
      for (int q = p + 1; q < e; ++q) Li[q - p - 1] -= a * L_[q];
      L_[p] = a;
    }
  }
  return true;
}

void TreeCholesky::solveLtOn(const std::vector<int>& support, double* x) const {
  for (auto it = support.rbegin(); it != support.rend(); ++it) {
    const int i = *it;
    const double xi = x[i];
    if (xi == 0) continue;
    for (int p = start_[i]; p < start_[i + 1]; ++p) x[anc_[p]] -= L_[p] * xi;
  }
}

void TreeCholesky::solveL(double* x) const {
  for (int i = 0; i < size(); ++i) {
    double xi = x[i];
    for (int p = start_[i]; p < start_[i + 1]; ++p) xi -= L_[p] * x[anc_[p]];
    x[i] = xi;
  }
}

void TreeCholesky::multiply(const Eigen::MatrixXd& A, const double* x, double* y) const {
  const int n = size();
  for (int j = 0; j < n; ++j) y[j] = A(j, j) * x[j];
  for (int j = 0; j < n; ++j)
    for (int p = start_[j]; p < start_[j + 1]; ++p) {  // A(i, j), i an ancestor of j (i < j): above the diagonal
      const int i = anc_[p];
      y[i] += A(i, j) * x[j];
      y[j] += A(i, j) * x[i];
    }
}

void TreeCholesky::solveInPlace(double* x) const {
  const int n = size();
  for (int i = n - 1; i >= 0; --i) {  // L^-T
    const double xi = x[i];
    for (int p = start_[i]; p < start_[i + 1]; ++p) x[anc_[p]] -= L_[p] * xi;
  }
  for (int i = 0; i < n; ++i) x[i] /= D_[i];
  solveL(x);
}

}  // namespace em
