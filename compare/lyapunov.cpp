#include "compare/lyapunov.hpp"

#include <cmath>
#include <tuple>
#include <utility>

#include "solver/dynamics.hpp"
#include "solver/perturb.hpp"
#include "solver/steppers.hpp"

namespace em {

namespace {

// One rk4 step of the pair's member y by h, with the classical method; false when it fails.
bool stepOne(Dynamics& dyn, double t, double h, Eigen::VectorXd& y, StepScratch& w) {
  auto evaluate = [&dyn](double tt, const double* yy, double* dy) { return dyn.rhs(tt, yy, dy).ok; };
  if (!rk4Step(Derivative(evaluate), t, h, y.data(), static_cast<int>(y.size()), w)) return false;
  StepInfo ignored;
  return dyn.afterStep(t + h, y.data(), ignored).ok;
}

// A fixed unit direction in the speeds: u_i proportional to 1 + i / N (no randomness).
Eigen::VectorXd speedDirection(const Model& m, int size) {
  Eigen::VectorXd v = Eigen::VectorXd::Zero(size);
  for (int i = 0; i < m.nu; ++i) v[m.nq + i] = 1.0 + double(i) / m.nu;
  return v / v.norm();
}

// Mean and sample standard deviation (n - 1) of x: NaN where there are too few.
std::pair<double, double> meanAndSpread(const std::vector<double>& x) {
  const double n = static_cast<double>(x.size());
  double mean = 0, var = 0;
  for (double v : x) mean += v / n;
  for (double v : x) var += (v - mean) * (v - mean) / (n - 1);
  return {x.empty() ? NAN : mean, x.size() < 2 ? NAN : std::sqrt(var)};
}

}  // namespace

Lyapunov lyapunovExponent(const Model& m, const LyapunovOptions& o) {
  Dynamics a(m, Method::Classical), b(m, Method::Classical);
  Eigen::VectorXd y = a.initialState(m.q0(), m.u0());
  const int n = m.nq + m.nu;  // the distance is over (q, u), not the dissipated work
  Eigen::VectorXd z = y + o.d0 * speedDirection(m, static_cast<int>(y.size()));
  StepScratch wa(static_cast<int>(y.size())), wb(static_cast<int>(y.size()));
  const long steps_per_renorm = std::max(1L, std::lround(o.renorm_s / o.dt));
  const long renorms_per_window = std::max(1L, std::lround(o.window_s / o.renorm_s));
  const long total = std::lround(o.t_end / (o.dt * steps_per_renorm));
  Lyapunov out;
  double sum = 0, window_sum = 0;
  long k = 0;
  for (; k < total; ++k) {
    bool ok = true;
    for (long s = 0; s < steps_per_renorm && ok; ++s) {
      const double t = (k * steps_per_renorm + s) * o.dt;
      ok = stepOne(a, t, o.dt, y, wa) && stepOne(b, t, o.dt, z, wb);
    }
    if (!ok) {
      out.ok = false;
      break;
    }
    const double d = (z.head(n) - y.head(n)).norm();
    const double growth = std::log(d / o.d0);
    sum += growth, window_sum += growth;
    z.head(n) = y.head(n) + (z.head(n) - y.head(n)) * (o.d0 / d);
    StepInfo ignored;
    b.afterStep((k + 1) * steps_per_renorm * o.dt, z.data(), ignored);  // re-normalizes the twin's quaternions
    if ((k + 1) % renorms_per_window == 0) {
      out.windows.push_back(window_sum / (renorms_per_window * steps_per_renorm * o.dt));
      window_sum = 0;
    }
  }
  out.t_stop = k * steps_per_renorm * o.dt;
  out.per_s = out.t_stop > 0 ? sum / out.t_stop : NAN;
  out.windows_std_per_s = meanAndSpread(out.windows).second;
  out.uncertainty_per_s = out.windows_std_per_s / std::sqrt(static_cast<double>(out.windows.size()));  // NaN for one window
  return out;
}

LyapunovStarts lyapunovOverStarts(const Model& m, const LyapunovOptions& o, int starts, double sigma, std::uint64_t seed) {
  LyapunovStarts out;
  out.sigma = sigma, out.seed = seed;
  std::vector<double> done;
  for (int k = 0; k < starts; ++k) {
    out.starts.push_back(lyapunovExponent(k == 0 ? m : perturbedStart(m, sigma, sigma, seed + static_cast<std::uint64_t>(k)), o));
    if (out.starts.back().ok) done.push_back(out.starts.back().per_s);
  }
  out.completed = static_cast<int>(done.size());
  std::tie(out.mean_per_s, out.spread_per_s) = meanAndSpread(done);
  return out;
}

LyapunovOptions longRunOptions(double horizon_s) {
  LyapunovOptions o;
  o.t_end = horizon_s;
  o.window_s = 10;
  return o;
}

}  // namespace em
