#pragma once
/// The extreme-case gallery (docs/extreme.md): every method through hard
/// scenes under several integrator settings, one compact entry per case x
/// setting x method with its outcome, the kind of its failure and the
/// diagnostics that explain it; a JSON summary, a Markdown page and a check
/// against a summary recorded earlier (the `extreme` test label).
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compare/comparison.hpp"

namespace em {

/// One integrator setting of a case, written "rk4:1e-3" (integrator:dt or tol).
struct ExtremeSetting {
  Integrator integrator = Integrator::RK4;
  double value = 1e-3;
  std::string key() const;    ///< "rk4:1e-3"
  std::string label() const;  ///< "rk4 dt 1e-3", "rk8pd tol 1e-10"
};
/// Parse "integrator:value" (an in-house integrator). Throws std::invalid_argument.
ExtremeSetting parseSetting(const std::string& text);

/// The settings every case runs under when neither the command line nor the scene names them.
std::vector<ExtremeSetting> defaultSettings();

/// A case: the scene and what its file says about it (`x-why`, `x-extreme`).
struct ExtremeCase {
  Scene scene;
  std::string path, why;
  std::vector<ExtremeSetting> settings;  ///< x-extreme.runs, else defaultSettings()
  std::optional<double> reference_tol;   ///< x-extreme.reference_tol
  /// x-extreme.reference_integrator: an in-house adaptive one in place of the
  /// default (a mechanism through singular positions, where ida's rows, chosen
  /// once, stop: rk8pd with the projection passes them).
  std::optional<Integrator> reference_integrator;
};
/// Load a case; a URDF has no x- keys. Throws one line naming the file and key.
ExtremeCase loadExtremeCase(const std::string& path, const UrdfOptions& urdf = {});

/// A run's first departure the gallery records (pose, rad): its `diverged_1e-3_s`
/// and the "pose>1e-3" column (kWrongRad, compare/metrics.hpp, judges the outcome).
constexpr double kDivergedRad = 1e-3;

/// What one method did in one case under one setting.
struct ExtremeEntry : RunEnd {  ///< how the run ended and its cost: its metrics', assigned whole
  std::string method;
  Outcome outcome = Outcome::Ok;
  std::optional<double> diverged_at;   ///< first time beyond kDivergedRad (pose)
  std::optional<double> wrong_at;      ///< first time beyond kWrongRad (pose)
  double max_pose = 0, max_energy = 0;
  bool eigenfactor = false;
  EigenStats eigen;
  std::string first_drift;             ///< first drift diagnostic above kDriftBound ("" if none)
  double first_drift_t = 0;
};

/// Drift diagnostics (orth_err, offdiag_rel, inv_err) count as moved above this.
constexpr double kDriftBound = 1e-6;

/// One setting of one case: the reference and every method.
struct ExtremeRun {
  ExtremeSetting setting;
  double reference_tol = 0, t_end = 0;
  Outcome reference_status = Outcome::Ok;
  std::string reference_failure;
  std::optional<double> horizon_wrong;  ///< reference horizon at kWrongRad
  std::string report;                   ///< the full report's file
  std::vector<ExtremeEntry> entries;
};

struct ExtremeCaseResult {
  std::string name, file, why;
  SceneSource source;
  int nu = 0;
  double cond_A0 = 0, lambda_min0 = 0, lambda_max0 = 0;  ///< A at the initial state
  std::vector<ExtremeRun> runs;
};

/// The compact entries of a comparison (its trajectories are then dropped).
ExtremeRun summarizeRun(const ComparisonResult& r, const ExtremeSetting& s);

/// How the gallery runs every case: methods, grid asked for (absent: each
/// scene's), thresholds of every method, where the full reports go.
struct ExtremeOptions {
  std::vector<Method> methods;
  Grid grid;
  MethodOptions options;
  std::string out_dir = "out/extreme";
};

/// Throws, naming the file and the setting, for a setting that cannot run on
/// the case (checked for every case before the gallery starts).
void checkExtremeCase(const ExtremeCase& c, const ExtremeOptions& opt);

/// Run one case under each of its settings, writing each full report into
/// opt.out_dir. `progress` may be null.
ExtremeCaseResult runExtremeCase(const ExtremeCase& c, const ExtremeOptions& opt, void (*progress)(const std::string&));
/// The report runExtremeCase writes for case `c` under setting `s` into `out_dir`.
std::string extremeReportPath(const std::string& out_dir, const ExtremeCase& c, const ExtremeSetting& s);

/// The summary `eigenmass-extreme/1` (docs/report-format.md).
nlohmann::json extremeJson(const std::vector<ExtremeCaseResult>& cases);

/// Why a run failed or went wrong, in one sentence drawn from its kind and
/// diagnostics only (never from the case's name).
std::string diagnosis(const ExtremeEntry& e, const ExtremeCaseResult& c, const ExtremeRun& run);

/// The Markdown page: the table, then a paragraph per case.
std::string extremeMarkdown(const std::vector<ExtremeCaseResult>& cases, const nlohmann::json& provenance);

/// Compare with a summary recorded earlier (a snapshot of this code's own
/// output, tests/extreme/expected.json): outcomes and failure kinds, the max
/// pose error of classical and articulated within 3x and failure times within 10 %; one line per
/// difference (empty when every entry matches). Every case x setting x method
/// run must be in `expected`, made with the same t_end.
std::vector<std::string> checkExpected(const std::vector<ExtremeCaseResult>& cases, const nlohmann::json& expected);
/// Throws std::invalid_argument ("not an extreme summary (key 'cases' not
/// found)") when `expected` is not a summary checkExpected can read: before any run.
void validateExpected(const nlohmann::json& expected);

}  // namespace em
