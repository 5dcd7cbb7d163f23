#pragma once
/// What one run is (RunSpec: engine and method, integrator and its step or
/// tolerance, output grid, thresholds), carried by the trajectory it makes,
/// and the checks every engine shares (settings, the output grid).
#include <functional>
#include <stdexcept>
#include <string>

#include "solver/method_options.hpp"
#include "solver/registry.hpp"

namespace em {

/// The tightest tolerance a run may ask (relative): double precision's rounding.
inline constexpr double kMinTolerance = 1e-16;

/// The fixed step when none is asked (s): the in-house rk4's and every fixed-step engine's.
inline constexpr double kDefaultDt = 1e-3;

/// What a scheme's one setting is: a fixed step dt (s) or a tolerance.
enum class SettingKind { Dt, Tolerance };
/// Its key in every file: "dt" or "tolerance".
inline const char* settingKindName(SettingKind k) { return k == SettingKind::Dt ? "dt" : "tolerance"; }
inline SettingKind settingKindOf(Integrator i) { return info(i).fixed_step ? SettingKind::Dt : SettingKind::Tolerance; }

/// One run, fully resolved (no "0 means the scene's"): what made a trajectory.
struct RunSpec {
  Method method = Method::Classical;
  Integrator integrator = Integrator::RK4;
  double dt = kDefaultDt;  ///< fixed step (fixed-step integrators)
  double tol = 1e-10;      ///< absolute and relative tolerance (adaptive; Simbody: accuracy)
  double t_end = 10.0;
  double output_dt = 0.01;
  bool diagnostics = true; ///< eigenfactor drift at every output time
  MethodOptions options;

  Engine engine() const { return info(method).engine; }
  bool fixedStep() const { return info(integrator).fixed_step; }
  SettingKind settingKind() const { return settingKindOf(integrator); }
  /// dt or tol, whichever the integrator uses.
  double setting() const { return fixedStep() ? dt : tol; }
  /// Set dt or tol, whichever the integrator uses (the one writer of "a setting").
  void setSetting(double x) { (fixedStep() ? dt : tol) = x; }
};

/// A run setting that cannot be used; `field` names it (t_end, output_dt, dt, tol).
struct SettingError : std::invalid_argument {
  SettingError(const std::string& field, const std::string& what)
      : std::invalid_argument(field + " " + what), field(field), detail(what) {}
  std::string field;
  std::string detail;  ///< the message without the field
  /// The same error told as the option the user typed: "--simbody-tol: Simbody's accuracy must be < 1, got 1".
  std::invalid_argument as(const std::string& option) const { return std::invalid_argument(option + ": " + detail); }
  /// The command line's option for the field: "--tol", "--dt", "--t-end", "--output-dt" (with `prefix`: "--simbody-tol").
  std::string option(const std::string& prefix = "") const {
    std::string o = field;
    for (char& c : o)
      if (c == '_') c = '-';
    return field == "tol" || field == "dt" ? "--" + prefix + o : "--" + o;
  }
};

/// A RunSpec that checkRunSpec has passed: the only spec a run accepts
/// (runTrajectory, simulate, an engine row's simulate), so settings are
/// checked once, where a command, a plan or the Python module resolves them,
/// and never again below. Made by checked() alone; read as a const RunSpec.
class CheckedRunSpec {
 public:
  const RunSpec& spec() const { return spec_; }
  operator const RunSpec&() const { return spec_; }
  const RunSpec* operator->() const { return &spec_; }

 private:
  explicit CheckedRunSpec(const RunSpec& s) : spec_(s) {}
  friend CheckedRunSpec checked(const RunSpec& s, const char* long_run_hint);
  RunSpec spec_;
};

/// Throws SettingError (or std::invalid_argument for a method and integrator
/// of different engines) unless `s` can be run as it stands. `long_run_hint`
/// ends the message of a run beyond the step budget: how the caller's user
/// raises it (the command line's --allow-long-run, a plan's max_steps).
void checkRunSpec(const RunSpec& s, const char* long_run_hint = "--allow-long-run goes ahead");
/// `s` checked by checkRunSpec, as the one type a run accepts.
CheckedRunSpec checked(const RunSpec& s, const char* long_run_hint = "--allow-long-run goes ahead");

/// Number of output intervals: t_end / output_dt, a whole number within
/// round-off. Throws SettingError otherwise.
long outputIntervals(double t_end, double output_dt);

/// Told the time of every output sample as a run records it (progress
/// display); may be empty. Its cost counts as sampling, not integration.
using SampleObserver = std::function<void(double t)>;

/// Fixed steps per output interval: output_dt / dt, whole within round-off.
long stepsPerOutput(double output_dt, double dt);

}  // namespace em
