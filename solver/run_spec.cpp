#include "solver/run_spec.hpp"

#include <cmath>

#include "solver/text.hpp"

namespace em {

namespace {

// Quotients of settings count as whole within this relative round-off.
constexpr double kWholeRel = 1e-9;

void requirePositive(const char* field, double x) {
  if (!std::isfinite(x)) throw SettingError(field, "must be a finite number, got " + gnum(x));
  if (!(x > 0)) throw SettingError(field, "must be > 0, got " + gnum(x));
}

// round(a / b) when a / b is whole within round-off, else -1.
long wholeQuotient(double a, double b) {
  const double r = a / b;
  const double n = std::nearbyint(r);
  if (!(n >= 1) || !(std::abs(r - n) <= kWholeRel * r) || n > 9.0e18) return -1;
  return static_cast<long>(n);
}

}  // namespace

long outputIntervals(double t_end, double output_dt) {
  requirePositive("t_end", t_end);
  requirePositive("output_dt", output_dt);
  const long n = wholeQuotient(t_end, output_dt);
  if (n < 1) throw SettingError("t_end", gnum(t_end) + " must be a whole multiple of output_dt " + gnum(output_dt));
  return n;
}

long stepsPerOutput(double output_dt, double dt) {
  requirePositive("dt", dt);
  const long n = wholeQuotient(output_dt, dt);
  if (n < 1) throw SettingError("dt", "does not fit: output_dt must be a whole multiple of dt (" + gnum(output_dt) +
                                          " / " + gnum(dt) + ")");
  return n;
}

void checkRunSpec(const RunSpec& s, const char* long_run_hint) {
  requireCompatible(s.method, s.integrator);
  const long intervals = outputIntervals(s.t_end, s.output_dt);
  if (double(intervals) + 1 > s.options.max_samples)
  {
    const auto [n, budget] = gnumApart(double(intervals) + 1, s.options.max_samples, 3);
    throw SettingError("output_dt", gnum(s.output_dt) + " over t_end " + gnum(s.t_end) + " s is " + n +
                                        " samples, more than the budget of " + budget + " (" + long_run_hint + ")");
  }
  if (!s.fixedStep()) {
    requirePositive("tol", s.tol);
    // Below double's rounding a tolerance means nothing, and a step derived from it underflows (a hostile
    // pass's --reference-tol 1e-300: IDA stopped at t = 0, its replacement at 1.4e-269 s, and compare said ok).
    if (s.tol < kMinTolerance)
      throw SettingError("tol", gnum(s.tol) + " is below " + gnum(kMinTolerance) + ", double precision's rounding: no integrator resolves it");
    // An engine may bound it (Simbody asserts, SIGABRT, on an accuracy >= 1): before any run.
    if (const double max = info(s.engine()).max_tol; !(s.tol < max))
      throw SettingError("tol", std::string(engineName(s.engine())) + "'s tolerance must be < " + gnum(max) + ", got " + gnum(s.tol));
    return;
  }
  const double steps = double(intervals) * double(stepsPerOutput(s.output_dt, s.dt));
  if (steps > s.options.max_steps) {
    const auto [n, budget] = gnumApart(steps, s.options.max_steps, 3);
    throw SettingError("dt", gnum(s.dt) + " over t_end " + gnum(s.t_end) + " s is " + n + " steps, more than the budget of " +
                                 budget + " (" + long_run_hint + ")");
  }
}

CheckedRunSpec checked(const RunSpec& s, const char* long_run_hint) {
  checkRunSpec(s, long_run_hint);
  return CheckedRunSpec(s);
}

}  // namespace em
