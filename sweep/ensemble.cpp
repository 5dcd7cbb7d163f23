#include "sweep/ensemble.hpp"

#include <algorithm>
#include <cmath>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_statistics_double.h>

#include "solver/perturb.hpp"

namespace em {

Model ensembleMember(const Model& m, const Ensemble& e, int k) {
  if (k == 0) return m;
  return perturbedStart(m, e.sigma_q, e.sigma_u, e.seed * 0x100000001B3ull + static_cast<std::uint64_t>(k));
}

std::string ensembleBeyondBounds(const Model& m, const Ensemble& e) {
  Eigen::VectorXd q = m.q0(), u = m.u0();
  const auto away = [](double x, double reach) { return x + std::copysign(reach, x); };
  for (const Body& b : m.bodies) {
    const int quat = jointQuat(b.joint.type);
    for (int k = 0; k < b.nq(); ++k)
      if (quat < 0 || k < b.nt()) q[b.iq + k] = away(q[b.iq + k], kDrawBound * e.sigma_q);  // a quaternion stays a unit one
    for (int k = 0; k < b.nu(); ++k) u[b.iu + k] = away(u[b.iu + k], kDrawBound * e.sigma_u);
  }
  return beyondStateBounds(m, q, u);
}

std::optional<double> quantile(std::vector<double> x, double p) {
  if (x.empty()) return std::nullopt;
  std::sort(x.begin(), x.end());
  const double h = p * static_cast<double>(x.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(h));
  const size_t hi = std::min(lo + 1, x.size() - 1);
  if (std::isinf(x[lo]) || std::isinf(x[hi])) return h > static_cast<double>(lo) ? x[hi] : x[lo];  // censored: not interpolated
  return gsl_stats_quantile_from_sorted_data(x.data(), 1, x.size(), p);
}

std::optional<std::pair<double, double>> medianInterval(std::vector<double> x, double level) {
  if (x.empty()) return std::nullopt;
  std::sort(x.begin(), x.end());
  const unsigned n = static_cast<unsigned>(x.size());
  // P(x_(l+1) <= median < x_(n-l)) = 1 - 2 P(B <= l), B ~ Binomial(n, 1/2).
  unsigned l = 0;
  while (l + 1 <= n / 2 && 1 - 2 * gsl_cdf_binomial_P(l, 0.5, n) >= level) ++l;
  return std::make_pair(x[std::max(l, 1u) - 1], x[n - std::max(l, 1u)]);
}

}  // namespace em
