#pragma once
/// One comparison: several methods on one scene against a reference, all on one
/// output grid (the main job of the harness; docs/report-format.md).
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "compare/metrics.hpp"
#include "compare/engines.hpp"
#include "compare/lyapunov.hpp"
#include "compare/sensitivity.hpp"

namespace em {

/// Tolerance of another engine as a compared method when none is asked (Simbody's accuracy).
constexpr double kEngineTol = 1e-6;

/// Whether engine `e` runs at the in-house step (and on the in-house scheme
/// where it has it) when compared: its default integrator takes a fixed step.
bool followsInHouse(Engine e);

struct CompareOptions {
  std::vector<Method> methods;  ///< default: every method of the registry, in table order
  /// Methods of the default list left out because their engine cannot take
  /// the scene (methodRefusal: "method: why"), each said in the table and the report.
  std::vector<std::pair<Method, std::string>> left_out;
  /// Leave out of `methods` those whose engine cannot take `m` (a default
  /// list: a method named by the user is refused instead), into left_out.
  void leaveOutRefused(const Model& m);
  /// The in-house methods `inhouse`'s integrator cannot run on `m`
  /// (refuseUnrunnable: ida or trapezoidal with a method's own state, the
  /// augmented Lagrangian and trapezoidal apart): left out into left_out, or,
  /// where the user named the methods (`named`), refused in one line.
  void leaveOutUnrunnable(const Model& m, bool named);
  RunSpec inhouse;           ///< integrator and step/tolerance of the in-house methods (rk4, dt kDefaultDt)
  /// Every other engine as a compared method, one spec each: its default
  /// integrator and tolerance kEngineTol (Simbody: rkmerson at 1e-6). A
  /// fixed-step engine's step is the in-house one, and so is its scheme where
  /// it has it, unless one was chosen (specFor; MuJoCo: rk4 at 1e-3).
  std::map<Engine, RunSpec> engines;
  /// Engines whose integrator the user chose (chooseIntegrator): kept as chosen.
  std::set<Engine> chosen;
  RunSpec reference;         ///< the reference run (defaultReferenceSpec(): Simbody rkmerson, accuracy 1e-10)
  double tight_factor = 100; ///< the horizon run is the reference at tolerance / tight_factor
  Grid grid;                 ///< t_end and output_dt asked for (absent: the scene's)
  std::vector<double> thresholds = {1e-3, 1e-1};
  /// Beside the reference, the second engine (the row whose roles say so:
  /// MuJoCo rk4 at 1e-4 s) on the grid: the distance of the two independent
  /// engines, a second floor (compare; the gallery leaves it out).
  bool second_engine = true;
  /// Horizon (s) of the reference motion's long-run Lyapunov exponent, measured
  /// apart from the grid's finite-time one (compare --lyapunov-long); 0: not measured.
  double lyapunov_long_s = 0;
  /// The long-run exponent from this many starts (compare --lyapunov-starts): the scene's own and
  /// neighbours displaced by lyapunov_sigma (lyapunovOverStarts); 1: the scene's start alone.
  int lyapunov_starts = 1;
  double lyapunov_sigma = 1e-3;
  /// The reference's sensitivity twin (compare/sensitivity.hpp): the reference
  /// again from a start 1e-10 away; where it parts by more than a threshold,
  /// that threshold is ill-conditioned on this scene (the report says so).
  bool sensitivity_twin = true;

  /// How a refused setting is named: the CLI's options ("--dt", "--t-end",
  /// "--reference-tol"), or, with `keywords`, the Python module's keyword
  /// arguments ("dt", "t_end").
  bool keywords = false;
  /// Set by useMechanismReference: the reference is the mechanism's default
  /// (IDA), which, where it stops before t_end (a singular position: its
  /// index-2 rows lose rank), is replaced by a route that passes singular
  /// positions and checked against IDA's span (ReferenceRuns::stopped).
  bool mechanism_reference = false;

  CompareOptions();
  /// A mechanism's reference is in-house, as no engine's is exact on loops
  /// at a tolerance: classical under ida at the reference's tolerance
  /// (docs/theory.md §15). A tree keeps its reference.
  void useMechanismReference(const Model& m);
  /// The settings a compared method runs with: `inhouse`, or its engine's,
  /// a fixed-step engine following the in-house step and scheme (above).
  /// The one place that rule is applied: no caller has to remember it.
  RunSpec specFor(Method method) const;
  /// Run engine `e` on `i` whatever the in-house scheme (--<engine>-integrator).
  void chooseIntegrator(Engine e, Integrator i);
  /// Every spec, the reference's included (to apply options common to all).
  std::vector<RunSpec*> allSpecs();
};

/// The in-house settings a caller asked for (the CLI's --integrator, --dt and
/// --tol, the Python module's keywords of the same names).
struct AskedInHouse {
  bool integrator = false, dt = false, tol = false;
};
/// Throws std::invalid_argument, one line, for an asked in-house setting that
/// none of o.methods reads (no in-house method, no fixed-step engine that
/// follows the in-house step or scheme): refused, never ignored. Named as
/// o.keywords says.
void refuseUnreadInHouseSettings(const CompareOptions& o, const AskedInHouse& asked);

struct ComparisonResult {
  std::string scene_name;
  SceneSource scene_source;
  int nq = 0, nu = 0, bodies = 0;
  CompareOptions options;
  double t_end = 0, output_dt = 0;             ///< the common grid (the reference run's)
  Trajectory reference, tight;
  std::vector<std::optional<double>> horizon;  ///< per threshold
  double reference_check_pose_rad = 0;  ///< the reference against its twin over the grid: the largest pose difference (rad)
  double energy_scale = 1;
  std::string energy_scale_definition;  ///< what energy_scale is (energyScaleOf)
  MethodMetrics reference_metrics;             ///< the reference's own energy error and cost
  std::vector<Trajectory> runs;                ///< per method, in options.methods order
  std::vector<MethodMetrics> metrics;
  /// The reference motion's maximal Lyapunov exponent over the grid (compare/lyapunov.hpp);
  /// absent where no comparison command asked for it (the gallery).
  std::optional<Lyapunov> lyapunov;
  /// Its long-run value over options.lyapunov_long_s, when asked (longRunOptions).
  std::optional<Lyapunov> lyapunov_long;
  /// Over several starts (options.lyapunov_starts > 1); its starts[0] is lyapunov_long.
  std::optional<LyapunovStarts> lyapunov_long_starts;
  /// The second engine (MuJoCo rk4 at a small step) against the reference,
  /// when asked and MuJoCo takes the scene; else why not.
  std::optional<Sensitivity> sensitivity;  ///< the reference's sensitivity twin, when run (options.sensitivity_twin)
  std::optional<Trajectory> second_engine;
  std::optional<MethodMetrics> second_engine_metrics;
  std::string second_engine_skipped;
  /// A mechanism's default reference that stopped before t_end (IDA at a
  /// singular position), measured against the reference that replaced it
  /// over its own span, and what was done (ReferenceRuns::stopped).
  std::optional<Trajectory> stopped_reference;
  std::optional<MethodMetrics> stopped_reference_metrics;
  std::string reference_note;
  /// Per engine that ran (the reference's, the second engine, a method's): what it does to this scene
  /// that bounds its agreement (engineSceneNote), where it says something.
  std::vector<std::pair<std::string, std::string>> engine_notes;
};


/// Throws for settings that cannot run (SettingError, a method named twice,
/// no threshold): what runComparison checks before anything runs.
void checkComparisonOptions(const Scene& scene, const CompareOptions& opt);

/// The reference run, its tighter twin (the horizon run) and the reference
/// motion's Lyapunov exponent over the grid: measured once per reference, and
/// shared by every comparison against it (the gallery's settings).
struct ReferenceRuns {
  Trajectory reference, tight;
  Lyapunov lyapunov;
  std::optional<Lyapunov> lyapunov_long;    ///< over CompareOptions::lyapunov_long_s, when asked
  std::optional<LyapunovStarts> lyapunov_long_starts;  ///< over lyapunov_starts starts, when more than one
  std::optional<Sensitivity> sensitivity;   ///< the reference's sensitivity twin (CompareOptions::sensitivity_twin; none with loops)
  std::optional<Trajectory> second_engine;  ///< the second engine's run (CompareOptions::second_engine; its row's roles)
  std::string second_engine_skipped;        ///< why it did not run, when asked
  /// A mechanism's default reference (IDA) where it stopped before t_end:
  /// that run, kept as the check of the reference that replaced it over its
  /// span, and what was done (CompareOptions::mechanism_reference).
  std::optional<Trajectory> stopped;
  std::string reference_note;
};
/// Run them as `opt` says (after checkComparisonOptions).
ReferenceRuns runReference(const Scene& scene, const CompareOptions& opt, void (*progress)(const std::string&) = nullptr);

/// Run every method and the reference (and its tighter twin), then compare.
/// `progress` (may be null) is told each run's name as it starts. Settings are
/// checked (and a method named twice refused) before anything runs.
ComparisonResult runComparison(const Scene& scene, const CompareOptions& opt,
                               void (*progress)(const std::string&) = nullptr);
/// The same against reference runs made earlier with the same reference
/// settings and grid (several in-house settings against one reference).
ComparisonResult runComparison(const Scene& scene, const CompareOptions& opt, const ReferenceRuns& reference,
                               void (*progress)(const std::string&) = nullptr);

/// Compare already computed runs (used by runComparison and by tests).
ComparisonResult compareTrajectories(const Trajectory& reference, const Trajectory& tight, std::vector<Trajectory> runs,
                             const CompareOptions& opt);

/// The compact human table: method, status, divergence times, max energy error, run time.
std::string summaryTable(const ComparisonResult& r);

}  // namespace em
