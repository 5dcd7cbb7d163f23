// Onto the loops (docs/theory.md §15, eqs. (M8), (M9), (M12)).
#include "solver/mechanism/projection.hpp"

#include <algorithm>
#include <cmath>

#include "solver/formation.hpp"

namespace em {

LoopProjector::LoopProjector(const Model& m)
    : loops_(m), solve_(m), llt_(m.nu), tree_(TreeCholesky::pays(m) ? std::make_unique<TreeCholesky>(m) : nullptr),
      AinvGt_(tree_ ? 0 : m.nu, tree_ ? 0 : m.loop_rows), dv_(m.nu), dq_(m.nq) {}

void LoopProjector::correction(const Eigen::VectorXd& r) {
  if (tree_) solve_.correction(loops_, *tree_, r, dv_);
  else solve_.correction(loops_, AinvGt_, r, dv_);
}

LoopProjector::Result LoopProjector::positions(const Model& m, Workspace& ws, double* q, const double* u, double tol,
                                               int iterations) {
  Result r;
  for (;;) {
    formKinematics(m, q, u, ws);
    formLoops(m, ws, u, loops_);
    formSubtrees(m, ws);
    formA(m, ws);
    if (tree_) {
      if (!tree_->factor(ws.A)) {  // A not positive definite: as the dense path's NaN would say
        r.finite = false;
        return r;
      }
    } else {
      llt_.compute(ws.A);
      AinvGt_.noalias() = llt_.solve(loops_.G.transpose());
    }
    // The true gap: g's direction rows also vanish at turns that are not the closure's (formLoops' turn).
    const double gap = std::max(loops_.position_m, loops_.position_rad);
    if (gap <= tol) {
      r.converged = true;
      return r;
    }
    if (!std::isfinite(gap)) {
      r.finite = false;
      return r;
    }
    if (r.iterations == iterations) return r;
    // dv = -A^-1 G^T (G A^-1 G^T)^+ g, q <- q + qdot(q, dv) (eq. (M8)).
    correction(loops_.g);
    dv_ = -dv_;
    formQdot(m, q, dv_.data(), dq_.data());
    Eigen::Map<Eigen::VectorXd>(q, m.nq) += dq_;
    normalizeQuaternions(m, q);
    ++r.iterations;
  }
}

void LoopProjector::velocities(double* u) {
  correction(loops_.Gu);  // eq. (M9)
  Eigen::Map<Eigen::VectorXd>(u, dv_.size()) -= dv_;
}

CoordinatePartition::CoordinatePartition(const Model& m)
    : Gd_(m.loop_rows, m.nu), qr_(m.loop_rows, m.nu), qr_d_(m.loop_rows, m.nu), step_(m.nu), dv_(m.nu), dq_(m.nq) {
  dependent_.reserve(m.nu);
  qr_.setThreshold(kLoopRankTol);
  qr_d_.setThreshold(kLoopRankTol);
}

namespace {
// The smallest pivot of a column-pivoted QR's first r, relative to its largest: 0 for r = 0.
double pivotRatio(const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr, int r) {
  if (r <= 0) return 1.0;
  const double first = std::abs(qr.matrixQR()(0, 0));
  return first > 0 ? std::abs(qr.matrixQR()(r - 1, r - 1)) / first : 0.0;
}
}  // namespace

int CoordinatePartition::choose(const LoopState& ls) {
  qr_.compute(ls.G);
  rank_ = static_cast<int>(qr_.rank());
  dependent_.assign(qr_.colsPermutation().indices().data(), qr_.colsPermutation().indices().data() + rank_);
  std::sort(dependent_.begin(), dependent_.end());
  best_ratio_ = pivotRatio(qr_, rank_);
  formGd(ls);
  return rank_;
}

void CoordinatePartition::formGd(const LoopState& ls) {
  Gd_.resize(ls.G.rows(), static_cast<Eigen::Index>(dependent_.size()));  // the same size while the partition holds: no allocation
  for (size_t k = 0; k < dependent_.size(); ++k) Gd_.col(static_cast<Eigen::Index>(k)) = ls.G.col(dependent_[k]);
  qr_d_.compute(Gd_);
}

bool CoordinatePartition::degraded(const LoopState& ls) {
  qr_.compute(ls.G);
  best_ratio_ = pivotRatio(qr_, static_cast<int>(qr_.rank()));
  if (static_cast<int>(qr_.rank()) != rank_) return true;
  formGd(ls);
  best_ratio_ = pivotRatio(qr_, rank_);
  return pivotRatio(qr_d_, rank_) * kRepartitionRatio < best_ratio_;
}

LoopProjector::Result CoordinatePartition::dependent(const Model& m, Workspace& ws, LoopState& ls, double* q, double* u,
                                                     double tol, int iterations) {
  LoopProjector::Result r;
  for (;;) {
    formKinematics(m, q, u, ws);
    formLoops(m, ws, u, ls);
    formGd(ls);
    const double gap = std::max(ls.position_m, ls.position_rad);
    if (!std::isfinite(gap)) {
      r.finite = false;
      return r;
    }
    if (gap <= tol || r.iterations == iterations) {
      r.converged = gap <= tol;
      break;
    }
    // G_d dv_d = -g (least squares on redundant rows), dv_i = 0; q <- q + qdot(q, dv) (eq. (M12)).
    step_.head(rank_) = qr_d_.solve(ls.g);
    dv_.setZero();
    for (int k = 0; k < rank_; ++k) dv_[dependent_[k]] = -step_[k];
    formQdot(m, q, dv_.data(), dq_.data());
    Eigen::Map<Eigen::VectorXd>(q, m.nq) += dq_;
    normalizeQuaternions(m, q);
    ++r.iterations;
  }
  // u_d -= G_d^+ (G u): then G u = 0 with u_i untouched.
  step_.head(rank_) = qr_d_.solve(ls.Gu);
  for (int k = 0; k < rank_; ++k) u[dependent_[k]] -= step_[k];
  return r;
}

}  // namespace em
