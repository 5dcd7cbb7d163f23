// eigen-block (docs/theory.md §8, not in the paper): A = C^T D C with C
// orthogonal and D block diagonal, one block per cluster of eigenvalues
// closer than delta; between blocks Omega solves a Sylvester equation, so it
// stays bounded where the paper's Omega_ij = G_ij / (lambda_j - lambda_i)
// blows up at a near-crossing. Blocks are contiguous ranges of rows of C;
// after every accepted step each block is diagonalized and the clusters are
// formed anew.
#include <algorithm>
#include <limits>
#include <numeric>

#include "solver/method.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

// Within-block Jacobi: diagonalize the blocks of the symmetric M in place,
// accumulating the rotations in U (M_final = U M_0 U^T); off-block entries
// of M are zero and stay so. Converges in one or two sweeps from a nearly
// diagonal M.
void diagonalizeBlocks(Eigen::MatrixXd& M, RowMatrix& U, const std::vector<int>& start) {
  U.setIdentity();
  const double bound = 1e-15 * M.norm();
  for (int sweep = 0; sweep < 30; ++sweep) {
    double off = 0;
    for (size_t b = 0; b + 1 < start.size(); ++b)
      for (int p = start[b]; p < start[b + 1]; ++p)
        for (int q = p + 1; q < start[b + 1]; ++q) off = std::max(off, std::abs(M(p, q)));
    if (off <= bound) return;
    for (size_t b = 0; b + 1 < start.size(); ++b)
      for (int p = start[b]; p < start[b + 1]; ++p)
        for (int q = p + 1; q < start[b + 1]; ++q)
          if (M(p, q) != 0.0) rotate(M, U, p, q);
  }
}

class EigenBlock final : public MethodImpl {
 public:
  EigenBlock(const Model& m, const MethodInfo& row, const MethodOptions& opt)
      : N_(m.nu), correction_(row.correction), refine_(static_cast<int>(row.param("refine", opt))),
        refine_tol_(row.param("refine_tol", opt)), delta_rel_(row.param("block_gap", opt)), opt_(opt), corr_(m.nu) {
    for (auto* X : {&Omega_, &AdotCt_, &Dblk_, &work_}) X->setZero(N_, N_);
    for (auto* X : {&U_, &W_}) X->setZero(N_, N_);
    eta_.setZero(N_);
    z_.setZero(N_);
    r_.setZero(N_);
    du_.setZero(N_);
    order_.resize(N_);
    old_block_.resize(N_);
    seen_old_.resize(N_);
    new_count_.resize(N_);
    start_.reserve(N_ + 1);
  }

  // x = [C (N*N, row-major), D (N*N, column-major, block diagonal)] (ExtraState::CD).
  bool needsAdot() const override { return true; }
  bool needsA() const override { return refine_ > 0; }
  bool correctsAfterStep() const override { return true; }  // re-clustering changes the state
  bool needsAAfterStep() const override { return correction_ != Correction::None; }  // only Jacobi reads A
  bool hasDiagnostics() const override { return true; }

  void initialize(const Workspace& ws, double* x) override {
    startFromEigensolver(ws.A, Eigen::Map<RowMatrix>(x, N_, N_), eta_);
    Eigen::Map<Eigen::MatrixXd>(x + N_ * N_, N_, N_) = eta_.asDiagonal();
    start_.clear();  // no clusters yet: every eigenvalue its own block, then cluster
    for (int i = 0; i <= N_; ++i) start_.push_back(i);
    StepInfo ignored;
    recluster(x, ignored);
  }

  Status rates(double t, const double*, const double*, const Workspace& ws, const double* x, double* udot, double* xdot, EvalInfo& info) override;
  Status afterStep(double t, const Workspace& ws, double* x, StepInfo& info) override;
  EigenDiagnostics diagnostics(const Workspace& ws, const double* x, double max_Omega) const override;

 private:
  // Dblk_ = D's blocks diagonalized (U_ holds the rotations), eta_ = diag Dblk_.
  void eigenOfBlocks(const double* x) {
    Dblk_ = Eigen::Map<const Eigen::MatrixXd>(x + N_ * N_, N_, N_);
    diagonalizeBlocks(Dblk_, U_, start_);
    eta_ = Dblk_.diagonal();
  }
  // X <- U X U^T (U^T X U when `back`), block by block; 1x1 blocks are left alone.
  void applyU(Eigen::MatrixXd& X, bool back);
  // out = C^T D^-1 C b (u' when b = B).
  void applyInverse(const Eigen::Ref<const RowMatrix>& C, const Eigen::VectorXd& b, Eigen::Ref<Eigen::VectorXd> out);
  // Omega between blocks from G = C A' C^T (in Omega_), in place: the Sylvester equations (docs/theory.md §8, eq. (S)).
  Status solveSylvesterBetweenBlocks(double t, double floor);
  void recluster(double* x, StepInfo& info);
  void countMergesSplits(StepInfo& info);
  bool sameBlock(int i, int j) const { return block_[i] == block_[j]; }

  int N_;
  Correction correction_;
  int refine_;        // residual corrections per evaluation (the row's option "refine")
  double refine_tol_;  // relative residual the last correction must reach (the row's option "refine_tol")
  double delta_rel_;  // delta / max eta: eigenvalues closer share a block (the row's option "block_gap")
  MethodOptions opt_;
  CorrectionScratch corr_;
  Eigen::MatrixXd Omega_, AdotCt_, Dblk_, work_;  // (N x N) scratch: G then Omega, A'C^T, D's eigenblocks, products
  RowMatrix U_, W_;                     // (N x N) within-block rotations; row scratch
  Eigen::VectorXd eta_, z_;              // (N) eigenvalues of D; D^-1 C b
  Eigen::VectorXd r_, du_;              // (N) residual B - A u' and its correction
  std::vector<int> start_;              // (blocks + 1) first row of each block
  std::vector<int> block_;              // (N) block of each row
  std::vector<int> order_, old_block_;  // (N) scratch of recluster
  std::vector<int> seen_old_, new_count_;  // (N) scratch of countMergesSplits
};

void EigenBlock::applyU(Eigen::MatrixXd& X, bool back) {
  for (size_t b = 0; b + 1 < start_.size(); ++b) {
    const int s0 = start_[b], s = start_[b + 1] - s0;
    if (s == 1) continue;
    const auto Ub = U_.block(s0, s0, s, s);
    if (back) work_.topRows(s).noalias() = Ub.transpose() * X.middleRows(s0, s);
    else work_.topRows(s).noalias() = Ub * X.middleRows(s0, s);
    X.middleRows(s0, s) = work_.topRows(s);
    if (back) work_.leftCols(s).noalias() = X.middleCols(s0, s) * Ub;
    else work_.leftCols(s).noalias() = X.middleCols(s0, s) * Ub.transpose();
    X.middleCols(s0, s) = work_.leftCols(s);
  }
}

void EigenBlock::applyInverse(const Eigen::Ref<const RowMatrix>& C, const Eigen::VectorXd& b, Eigen::Ref<Eigen::VectorXd> out) {
  // C^T D^-1 C b, D^-1 = U^T diag(1/eta) U block by block (U_, eta_ from eigenOfBlocks).
  z_.noalias() = C * b;
  for (size_t k = 0; k + 1 < start_.size(); ++k) {
    const int s0 = start_[k], s = start_[k + 1] - s0;
    if (s == 1) { z_[s0] /= eta_[s0]; continue; }
    const auto Ub = U_.block(s0, s0, s, s);
    work_.col(0).head(s).noalias() = Ub * z_.segment(s0, s);
    work_.col(0).head(s).array() /= eta_.segment(s0, s).array();
    z_.segment(s0, s).noalias() = Ub.transpose() * work_.col(0).head(s);
  }
  out.noalias() = C.transpose() * z_;
}

Status EigenBlock::solveSylvesterBetweenBlocks(double t, double floor) {
  // In the blocks' eigenbases: Omega~_ij (eta_j - eta_i) = G~_ij between blocks, 0 inside.
  applyU(Omega_, false);
  for (int j = 0; j < N_; ++j)
    for (int i = 0; i < N_; ++i) {
      if (sameBlock(i, j)) { Omega_(i, j) = 0; continue; }
      const double gap = eta_[j] - eta_[i];
      if (!(std::abs(gap) >= floor))
        return Status::failure(t, Failure::EigenGap, "gap between blocks |eta_" + std::to_string(i) + " - eta_" + std::to_string(j) +
                                      "| = " + gnum(std::abs(gap)) + " below the floor " + gnum(floor));
      Omega_(i, j) /= gap;
    }
  // Back to the rows of C: Omega = U^T Omega~ U.
  applyU(Omega_, true);
  return {};
}

Status EigenBlock::rates(double t, const double*, const double*, const Workspace& ws, const double* x, double* udot, double* xdot, EvalInfo& info) {
  Eigen::Map<const RowMatrix> C(x, N_, N_);
  Eigen::Map<RowMatrix> Cdot(xdot, N_, N_);
  Eigen::Map<Eigen::MatrixXd> Ddot(xdot + N_ * N_, N_, N_);
  eigenOfBlocks(x);
  const double lmax = eta_.maxCoeff(), floor = opt_.gap_floor_rel * lmax;
  for (int i = 0; i < N_; ++i)
    if (!(eta_[i] > 0)) return Status::failure(t, Failure::NonPositiveEigenvalue, "eigenvalue of D " + gnum(eta_[i]) + " <= 0 (block " + std::to_string(block_[i]) + ")");
  // G = C A' C^T (symmetric; upper half formed, then mirrored), in Omega_.
  AdotCt_.noalias() = ws.Adot * C.transpose();
  Omega_.triangularView<Eigen::Upper>() = C * AdotCt_;
  Omega_.triangularView<Eigen::StrictlyLower>() = Omega_.transpose();
  // Inside a block: Omega = 0 and D' = G (eq. (D')); between blocks D' = 0.
  Ddot.setZero();
  for (size_t b = 0; b + 1 < start_.size(); ++b) {
    const int s0 = start_[b], s = start_[b + 1] - s0;
    Ddot.block(s0, s0, s, s) = Omega_.block(s0, s0, s, s);
  }
  const Status sylvester = solveSylvesterBetweenBlocks(t, floor);
  if (!sylvester) return sylvester;
  info.max_Omega = Omega_.cwiseAbs().maxCoeff();
  Cdot.noalias() = -Omega_ * C;
  // u' = H B with H = C^T D^-1 C, then refine_ residual corrections.
  const auto applyH = [&](const Eigen::VectorXd& b, Eigen::Ref<Eigen::VectorXd> out) { applyInverse(C, b, out); };
  return solveByEigenfactors(t, ws, refine_, refine_tol_, applyH, Eigen::Map<Eigen::VectorXd>(udot, N_), r_, du_);
}

Status EigenBlock::afterStep(double t, const Workspace& ws, double* x, StepInfo& info) {
  Eigen::Map<RowMatrix> C(x, N_, N_);
  Eigen::Map<Eigen::MatrixXd> D(x + N_ * N_, N_, N_);
  // Each block diagonalized: C's rows of the block rotated by its U, D <- diag(eta).
  eigenOfBlocks(x);
  for (size_t b = 0; b + 1 < start_.size(); ++b) {
    const int s0 = start_[b], s = start_[b + 1] - s0;
    if (s == 1) continue;
    W_.topRows(s).noalias() = U_.block(s0, s0, s, s) * C.middleRows(s0, s);
    C.middleRows(s0, s) = W_.topRows(s);
  }
  if (correction_ == Correction::Jacobi) {  // the paper's correction on the now diagonal D
    const Status s = jacobiCorrectAt(t, ws.A, C, eta_, corr_, opt_, info);
    if (!s) return s;
  }
  D.setZero();
  D.diagonal() = eta_;
  recluster(x, info);
  return {};
}

void EigenBlock::recluster(double* x, StepInfo& info) {
  Eigen::Map<RowMatrix> C(x, N_, N_);
  Eigen::Map<Eigen::MatrixXd> D(x + N_ * N_, N_, N_);
  eta_ = D.diagonal();
  std::iota(order_.begin(), order_.end(), 0);
  std::sort(order_.begin(), order_.end(), [this](int a, int b) { return eta_[a] < eta_[b]; });
  if (block_.empty()) block_.assign(N_, 0), std::iota(block_.begin(), block_.end(), 0);
  old_block_ = block_;
  const double delta = delta_rel_ * eta_.maxCoeff();
  // Sorted neighbours share a block when closer than delta, or 2 delta if they already did.
  start_.assign(1, 0);
  info.min_gap = std::numeric_limits<double>::infinity();
  for (int k = 1; k < N_; ++k) {
    const int a = order_[k - 1], b = order_[k];
    const double gap = eta_[b] - eta_[a];
    const bool together = gap < delta || (old_block_[a] == old_block_[b] && gap < 2 * delta);
    if (!together) {
      start_.push_back(k);
      info.min_gap = std::min(info.min_gap, gap);
    }
  }
  start_.push_back(N_);
  countMergesSplits(info);
  // Rows of C and entries of D in sorted order, so that blocks are contiguous.
  for (int k = 0; k < N_; ++k) W_.row(k) = C.row(order_[k]);
  C = W_;
  for (int k = 0; k < N_; ++k) z_[k] = eta_[order_[k]];
  eta_ = z_;
  D.diagonal() = eta_;
  for (size_t b = 0; b + 1 < start_.size(); ++b)
    for (int k = start_[b]; k < start_[b + 1]; ++k) block_[k] = static_cast<int>(b);
}

void EigenBlock::countMergesSplits(StepInfo& info) {
  // New block c (sorted positions start_[c]..) against the old blocks of its rows:
  // a new block holding rows of m old blocks is m - 1 merges; an old block
  // whose rows went to m new blocks is m - 1 splits.
  std::fill(seen_old_.begin(), seen_old_.end(), -1);
  std::fill(new_count_.begin(), new_count_.end(), 0);
  for (size_t c = 0; c + 1 < start_.size(); ++c) {
    int distinct = 0;
    for (int k = start_[c]; k < start_[c + 1]; ++k) {
      const int ob = old_block_[order_[k]];
      if (seen_old_[ob] != static_cast<int>(c)) {
        seen_old_[ob] = static_cast<int>(c);
        ++distinct;
        ++new_count_[ob];
      }
    }
    info.merges += distinct - 1;
  }
  for (int ob = 0; ob < N_; ++ob) info.splits += std::max(0, new_count_[ob] - 1);
}

EigenDiagnostics EigenBlock::diagnostics(const Workspace& ws, const double* x, double max_Omega) const {
  // At a sample, after a step: D is diagonal (eta), blocks as clustered.
  Eigen::Map<const RowMatrix> C(x, N_, N_);
  const Eigen::VectorXd eta = Eigen::Map<const Eigen::MatrixXd>(x + N_ * N_, N_, N_).diagonal();
  EigenDiagnostics d;
  d.orth_err = (C * C.transpose() - Eigen::MatrixXd::Identity(N_, N_)).norm();
  Eigen::MatrixXd CACt = C * ws.A * C.transpose();
  for (int j = 0; j < N_; ++j)
    for (int i = 0; i < N_; ++i)
      if (block_[i] == block_[j]) CACt(i, j) = 0;  // only what lies between blocks is drift
  d.offdiag_rel = CACt.norm() / ws.A.norm();
  d.min_gap = std::numeric_limits<double>::infinity();
  for (size_t b = 1; b + 1 < start_.size(); ++b) d.min_gap = std::min(d.min_gap, eta[start_[b]] - eta[start_[b] - 1]);
  d.max_Omega = max_Omega;
  const Eigen::MatrixXd Ainv = ws.A.inverse();
  d.inv_err = (C.transpose() * eta.cwiseInverse().asDiagonal() * C - Ainv).norm() / Ainv.norm();
  return d;
}

}  // namespace

std::unique_ptr<MethodImpl> makeEigenBlock(const Model& m, const MethodInfo& row, const MethodOptions& opt) {
  return std::make_unique<EigenBlock>(m, row, opt);
}

}  // namespace em
