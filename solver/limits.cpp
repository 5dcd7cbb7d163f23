#include "solver/limits.hpp"

#include <algorithm>
#include <cmath>

#include "solver/formation.hpp"

namespace em {

JointLimitEvents::JointLimitEvents(const Model& m)
    : m_(m), ws_(m), llt_(m.nu), col_(m.nu), u_(m.nu), held_(m.limited.size(), 0) {
  held_u_.reserve(m.limited.size());
}

double JointLimitEvents::inside(const double* y, size_t c) const {
  const LimitedCoordinate& l = m_.limited[c];
  return std::min(y[l.q] - l.lower, l.upper - y[l.q]);
}

int JointLimitEvents::beyond(const double* y) const {
  for (size_t c = 0; c < m_.limited.size(); ++c)
    if (!held_[c] && inside(y, c) < 0) return static_cast<int>(c);
  return -1;
}

bool JointLimitEvents::anyHeld() const {
  return std::any_of(held_.begin(), held_.end(), [](int h) { return h != 0; });
}

void JointLimitEvents::formA(const double* y) {
  formKinematics(m_, y, y + m_.nq, ws_);
  formSubtrees(m_, ws_);
  em::formA(m_, ws_);
  llt_.compute(ws_.A);
}

double JointLimitEvents::kinetic(const double* u) const {
  const Eigen::Map<const Eigen::VectorXd> v(u, m_.nu);
  return 0.5 * v.dot(ws_.A * v);
}

// Newton's law on speed k = l.u: u_k+ = -e u_k-. The impulse iota on that
// coordinate changes u by A^-1 e_k iota (the other speeds through the tree's
// coupling), so iota = -(1 + e) u_k- / (A^-1)_kk (docs/theory.md eq. (L2)).
void JointLimitEvents::impact(double t, double* y, int c, const double* udot_free) {
  const LimitedCoordinate& l = m_.limited[static_cast<size_t>(c)];
  const int side = y[l.q] - l.lower < l.upper - y[l.q] ? -1 : 1;
  y[l.q] = side < 0 ? l.lower : l.upper;
  formA(y);
  double* u = y + m_.nq;
  const double before = u[l.u], T0 = kinetic(u);
  const bool slow = std::abs(before) < kRestSpeed;
  const double e = slow ? 0.0 : l.restitution;
  col_.setZero();
  col_[l.u] = 1;
  col_ = llt_.solve(col_);  // A^-1 e_k
  const double iota = -(1 + e) * before / col_[l.u];
  for (int i = 0; i < m_.nu; ++i) u[i] += col_[i] * iota;
  // e = 0 (or a Zeno sequence's end) with the free acceleration into the stop: it rests there.
  const bool into = udot_free && side * udot_free[l.u] > 0;
  const bool rests = e == 0 && (slow || into);
  if (rests) {
    held_[static_cast<size_t>(c)] = side;
    u[l.u] = 0;
  }
  const double lost = T0 - kinetic(u);
  lost_ += lost;
  ++count_;
  if (impacts_.size() < kImpactsKept) impacts_.push_back({t, l.name, before, u[l.u], lost, rests});
}

// The held coordinates H: u' <- u' - A^-1 E (E^T A^-1 E)^-1 E^T u', which
// zeroes u'_H with contact forces on H alone (Gauss's principle; eq. (L3)).
void JointLimitEvents::constrain(const double* y, double* dydt) {
  formA(y);
  held_u_.clear();  // reserved at construction: no allocation per evaluation
  for (size_t c = 0; c < held_.size(); ++c)
    if (held_[c]) held_u_.push_back(m_.limited[c].u);
  const int h = static_cast<int>(held_u_.size());
  AinvE_.resize(m_.nu, h);  // a no-op while the held set keeps its size
  S_.resize(h, h);
  r_.resize(h);
  for (int j = 0; j < h; ++j) {
    col_.setZero();
    col_[held_u_[j]] = 1;
    AinvE_.col(j) = llt_.solve(col_);
  }
  double* udot = dydt + m_.nq;
  for (int i = 0; i < h; ++i) {
    r_[i] = udot[held_u_[i]];
    for (int j = 0; j < h; ++j) S_(i, j) = AinvE_(held_u_[i], j);
  }
  r_ = S_.llt().solve(r_);  // the contact forces (E^T A^-1 E is positive definite)
  for (int i = 0; i < m_.nu; ++i) udot[i] -= AinvE_.row(i).dot(r_);
  for (size_t c = 0; c < held_.size(); ++c)
    if (held_[c]) udot[m_.limited[c].u] = 0, dydt[m_.limited[c].q] = 0;
}

void JointLimitEvents::release(const double* y, const double* udot_free) {
  for (size_t c = 0; c < held_.size(); ++c)
    if (held_[c] && held_[c] * udot_free[m_.limited[c].u] < 0) held_[c] = 0;  // pulled away from the stop
  (void)y;
}

}  // namespace em
