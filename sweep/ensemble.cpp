#include "sweep/ensemble.hpp"

#include <algorithm>
#include <cmath>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_statistics_double.h>

#include "solver/rotation.hpp"

namespace em {

namespace {

// SplitMix64 (Steele, Lea, Flood 2014): a portable 64-bit stream from one seed.
class Draws {
 public:
  explicit Draws(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Uniform in (0, 1]: 53 random bits.
  double uniform() { return (static_cast<double>(next() >> 11) + 1.0) * 0x1.0p-53; }
  // Standard normal by Box–Muller (the cosine branch only: one draw per pair).
  double normal() {
    const double r = std::sqrt(-2.0 * std::log(uniform()));
    return r * std::cos(2.0 * M_PI * uniform());
  }

 private:
  std::uint64_t state_;
};

// Quaternion of the rotation vector v (angle |v| about v / |v|).  // (4)
Vec4 quatOfRotationVector(const Vec3& v) {
  const double angle = v.norm();
  if (angle == 0) return Vec4(1, 0, 0, 0);
  const Vec3 axis = v / angle;
  const double s = std::sin(0.5 * angle);
  return Vec4(std::cos(0.5 * angle), s * axis.x(), s * axis.y(), s * axis.z());
}

}  // namespace

Model ensembleMember(const Model& m, const Ensemble& e, int k) {
  Model out = m;
  if (k == 0) return out;
  Draws draws(e.seed * 0x100000001B3ull + static_cast<std::uint64_t>(k));
  std::vector<int> by_file(m.n());
  for (int i = 0; i < m.n(); ++i) by_file[m.bodies[i].file_index] = i;
  for (int i : by_file) {
    Joint& j = out.bodies[i].joint;
    const int at = jointQuat(j.type);
    for (int c = 0; c < jointNt(j.type); ++c) j.q0[c] += e.sigma_q * draws.normal();  // metres: the same sigma
    if (at >= 0) {
      const Vec3 v(draws.normal(), draws.normal(), draws.normal());
      j.q0.segment<4>(at) = quatMul(Vec4(j.q0.segment<4>(at)), quatOfRotationVector(e.sigma_q * v)).normalized();
    } else {
      for (int c = jointNt(j.type); c < j.q0.size(); ++c) j.q0[c] += e.sigma_q * draws.normal();
    }
    for (int c = 0; c < j.u0.size(); ++c) j.u0[c] += e.sigma_u * draws.normal();
  }
  return out;
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
