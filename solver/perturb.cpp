#include "solver/perturb.hpp"

#include <cmath>
#include <vector>

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

Model perturbedStart(const Model& m, double sigma_q, double sigma_u, std::uint64_t seed) {
  Model out = m;
  Draws draws(seed);
  std::vector<int> by_file(m.n());
  for (int i = 0; i < m.n(); ++i) by_file[m.bodies[i].file_index] = i;
  for (int i : by_file) {
    Joint& j = out.bodies[i].joint;
    const int at = jointQuat(j.type);
    for (int c = 0; c < jointNt(j.type); ++c) j.q0[c] += sigma_q * draws.normal();  // metres: the same sigma
    if (at >= 0) {
      const Vec3 v(draws.normal(), draws.normal(), draws.normal());
      j.q0.segment<4>(at) = quatMul(Vec4(j.q0.segment<4>(at)), quatOfRotationVector(sigma_q * v)).normalized();
    } else {
      for (int c = jointNt(j.type); c < j.q0.size(); ++c) j.q0[c] += sigma_q * draws.normal();
    }
    for (int c = 0; c < j.u0.size(); ++c) j.u0[c] += sigma_u * draws.normal();
  }
  return out;
}

}  // namespace em
