#pragma once
/// `eigenmass sweep` (docs/sweep.md): a plan's cases, each run on its own and
/// written to its own result file (so a sweep resumes, and fans out over
/// GNU parallel or a Slurm array as well as over local worker processes),
/// then merged into one CSV and the tables of error against run time and of
/// cost against size.
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sweep/plan.hpp"

namespace em {

struct Interleaved;  // below: interleaved timings of a few runs

/// The thresholds (rad) a case records its first times beyond, in this order;
/// its files name each after compare's thresholdKey ("pose_beyond_1e-3_s").
inline constexpr std::array<double, 2> kCaseThresholds = {1e-3, 1e-1};
using FirstTimes = std::array<std::optional<double>, kCaseThresholds.size()>;  ///< one per kCaseThresholds

/// What one case's result file says (`eigenmass-sweep-case/1`).
struct CaseRecord {
  std::string name;
  CaseRole role = CaseRole::Run;  ///< written as caseRoleName
  std::string scene, method, integrator;
  std::string formulation;   ///< a line's formulation that names the case (empty: the plan's, or a tree)
  std::string tuning;        ///< its line's tuning set (Tuning::label; empty: none)
  int member = 0;            ///< ensemble member (0: the scene itself)
  SettingKind setting_kind = SettingKind::Dt;
  double setting = 0;
  int nu = 0;
  Outcome status = Outcome::Ok;  ///< Ok or Failed
  Failure failure_kind = Failure::None;  ///< written as failureName
  std::string failure;
  std::optional<double> failure_time;
  bool has_error = false;  ///< errors against the plan's reference
  double max_pose = 0, max_coord = 0, max_energy = 0;
  FirstTimes pose_beyond;   ///< first time beyond each of kCaseThresholds (pose)
  FirstTimes coord_beyond;  ///< the same for the joint coordinates
  /// Runs: the largest pose error up to t0 = t_end / 10 (the early level the
  /// Lyapunov prediction starts from). References: their motion's exponent.
  std::optional<double> t0, pose_by_t0;
  std::optional<double> lyapunov_per_s, lyapunov_uncertainty_per_s;
  /// References: the sensitivity twin's largest pose difference (rad) from a
  /// start 1e-10 away (compare/sensitivity.hpp), and where the twin stopped if it did.
  std::optional<double> sensitivity_rad, sensitivity_failed_at;
  /// Free systems (compare/momenta.hpp): the largest relative drift of p - M g t and of H about the CM.
  std::optional<double> momentum_p, momentum_H;
  std::optional<double> joint_separation;    ///< m: a maximal-coordinate engine's constraint violation (ODE)
  /// A mechanism's run: its loops' largest violation, position (m, rad) and velocity (m/s, rad/s).
  std::optional<double> loop_position_m, loop_position_rad, loop_velocity_m, loop_velocity_rad;
  /// A benchmark scene's error measure against the reference (compare/benchmark.hpp), m, and when.
  std::optional<double> benchmark_error, benchmark_error_t;
  std::vector<double> cpu_s;                 ///< integration CPU time of every repeat
  long steps = 0, rhs_evals = 0;
  /// In-house adaptive runs: steps the output grid cut short (Trajectory::grid_cut_steps); absent for other schemes.
  std::optional<long> grid_cut_steps;
  bool repeats_identical = true;             ///< every repeat ended in the same state, bit for bit
  /// Eigenfactor methods: smallest eigenvalue gap (eigen-block: between blocks), largest |Omega|,
  /// Jacobi sweeps, eigen-block's merges and splits (absent for other methods).
  std::optional<EigenStats> eigen;

  double cpuMedian() const;
  double cpuMin() const;
  double cpuMax() const;
};

/// A case file's "result" and back; reading throws std::runtime_error naming `source`.
nlohmann::json caseRecordJson(const CaseRecord& r);
CaseRecord readCaseRecord(const nlohmann::json& j, const std::string& source);

/// The file of a case's result, and of its trajectory CSV (plans with the trajectories table).
std::string caseFile(const std::string& dir, const SweepCase& c);
std::string caseCsv(const std::string& dir, const SweepCase& c);

/// Run one case and write its result file (a reference case: with its
/// trajectory; a run needing the reference reads it, or runs and writes it
/// first when no other case has). A case whose file exists is not run again
/// (true is returned when it ran); a file made by another plan or another
/// scene file is refused, naming it.
bool runCase(const Plan& plan, const SweepCase& c, const std::string& dir);

/// Whether `c` has a result file made from this plan and scene. Throws for a
/// file made otherwise (another t_end, another scene content).
bool caseDone(const Plan& plan, const SweepCase& c, const std::string& dir);

/// Run every case not done yet on `jobs` worker processes (references
/// first), with progress on stderr. Returns the number of cases that could
/// not be run (their names and causes said on stderr).
int runSweep(const Plan& plan, const std::string& dir, int jobs);

/// One shell command per case (`eigenmass sweep PLAN --case NAME --results DIR`).
std::vector<std::string> listCommands(const Plan& plan, const std::string& plan_path, const std::string& dir);

/// Merged results of every case file present; `missing` gets the cases without one.
std::vector<CaseRecord> collectRecords(const Plan& plan, const std::string& dir, std::vector<std::string>& missing);

/// The merged CSV: one row per case (timing columns last, named cpu_*); a
/// plan with an ensemble adds the member after the scene.
std::string mergedCsv(const std::vector<CaseRecord>& records, bool with_member = false);

/// How the members of an ensemble crossed one threshold of one metric.
struct Distribution {
  int members = 0, diverged = 0, failed = 0;  ///< diverged: crossed (failures count, at their time)
  /// Over all members, one that never crossed counted as later than t_end
  /// (+inf: censored everywhere, as tools/ensemble_summary.py counts it).
  std::optional<double> median, q1, q3, min, max;
  std::optional<std::pair<double, double>> median_ci;  ///< the median's 95 % interval (medianInterval)
};
/// One row of `<plan>-ensemble.csv`: scene x method x integrator x setting x metric (pose, joint) x threshold.
struct EnsembleRow {
  std::string scene, method, integrator;  ///< method "reference-horizon": the check
  SettingKind setting_kind = SettingKind::Dt;
  double setting = 0;
  std::string metric;  ///< "pose" or "joint"
  double threshold = 0;
  Distribution d;
};
/// The rows of the records' runs and checks, in plan order.
std::vector<EnsembleRow> ensembleRows(const std::vector<CaseRecord>& records);
std::string ensembleCsv(const std::vector<EnsembleRow>& rows);
/// The same as a Markdown section of the tables page.
std::string ensembleTable(const std::vector<EnsembleRow>& rows);

/// One run's divergence time predicted from its early error and its
/// member's Lyapunov exponent, t0 + ln(threshold / e(t0)) / chi, beside the measured one.
struct Prediction {
  const CaseRecord* record = nullptr;
  double threshold = 0, chi = 0, e0 = 0;  // chi: the Lyapunov exponent (docs/theory.md §11)
  std::optional<double> predicted, measured;  ///< predicted: none when chi <= 0 or e(t0) is not below the threshold
};
/// For every run with an early error and a reference exponent, at 1e-3 and 0.1 rad (pose).
std::vector<Prediction> predictions(const std::vector<CaseRecord>& records);
std::string predictionCsv(const std::vector<Prediction>& rows);
std::string predictionTable(const std::vector<Prediction>& rows);

/// The tables of the plan (reference check, work-precision with the time to
/// reach 1e-3 and 1e-6 rad and the observed orders, cost against size with
/// fitted exponents) as Markdown.
/// `missing`: the plan's cases without a result, said at the top of the page
/// (and no goal judged) when there are any.
/// `timed`: the engine study's contenders timed in interleaved rounds (its margins' intervals).
std::string sweepTables(const Plan& plan, const std::vector<CaseRecord>& records, const std::vector<std::string>& missing = {},
                        const Interleaved* timed = nullptr);

/// Write `<plan>.csv` and `<plan>.md` into `dir` (and `<plan>-ensemble.csv`
/// for a plan with an ensemble); returns the Markdown.
std::string writeMerged(const Plan& plan, const std::string& dir, const std::vector<CaseRecord>& records,
                        const std::vector<std::string>& missing = {}, const Interleaved* timed = nullptr);

// Pieces of the tables, tested on their own.

/// A table cell in scientific notation ("1.23e-04"; "-" when not finite).
std::string sciCell(double x, int digits = 2);
/// A run's CPU per simulated second (up to its failure when it failed).
double cpuPerSimulatedSecond(const CaseRecord& r, double t_end);

/// Who a route belongs to: an engine's name, kInHouseOwner for the in-house
/// methods, else the method's own name (a plugin, an engine's u' under our integrators).
std::string routeOwner(const std::string& method);
/// Who a route belongs to in the benchmark: an integrator whose row owns its
/// routes (routeOwningIntegrator: IDA), else routeOwner(method).
std::string benchmarkOwner(const std::string& method, const std::string& integrator);
/// Whether the integrator's routes are its own in the benchmark: a DAE
/// solver (IDA) integrates our formation but is not ours (the goal is to beat it).
bool routeOwningIntegrator(const IntegratorInfo& i);
/// The engine study's tables of one scene (sweep/engine_study.cpp): each
/// route's cheapest run within 1e-3 and 1e-6 rad, each owner's fastest route
/// and whether eigenmass's is the cheapest, every run's errors, drifts and cost.
/// `floor`: the reference's check's largest pose difference (an accuracy below ten times it is said unresolved).
/// `judge`: false where cases are missing (a goal is then not judged, said so).
/// `output_dt`: the plan's, named where the output grid set an adaptive route's steps.
/// `timed`: interleaved rounds of the contenders (engineStudyContenders), which
/// give each margin its interval; none: margins from the medians, said so.
std::string engineStudyScene(const std::vector<CaseRecord>& records, const std::string& scene, double t_end, double output_dt,
                             double floor, bool judge = true, const Interleaved* timed = nullptr);
/// Across `scenes`: per owner, on how many each accuracy was reached and where its route was the fastest;
/// eigenmass's verdicts with their intervals where `timed`.
std::string engineStudySummary(const std::vector<CaseRecord>& records, const std::vector<std::string>& scenes, double t_end,
                               const Interleaved* timed = nullptr);
/// The runs the engine study's margins compare: on each scene, at each accuracy
/// it judges, eigenmass's fastest run and the cheapest other owners' (every
/// route, and the engines' own u' under the in-house integrators alone).
std::vector<std::string> engineStudyContenders(const std::vector<CaseRecord>& records, const std::vector<std::string>& scenes, double t_end);

/// The benchmark's tables of one scene (sweep/benchmark_tables.cpp): each
/// route's (method, formulation, scheme) cheapest run within each of `spec`'s
/// precision levels by its error measure, with that run's violation and
/// energy error, or why it never got there; each owner's fastest route, and
/// whether eigenmass's is the cheapest. `t_end`: the plan's horizon.
std::string benchmarkScene(const std::vector<CaseRecord>& records, const std::string& scene, const BenchmarkSpec& spec,
                           double t_end, bool judge = true);

/// Interleaved timings of a few runs (issue 76: a margin has an interval):
/// round k runs each case once, in turn, so that the machine's drift over
/// minutes falls on every case of a round alike. cpu_s[name][k]: round k's
/// integration CPU time (s).
struct Interleaved {
  int rounds = 0;
  std::map<std::string, std::vector<double>> cpu_s;
};
/// Rounds of interleaved timing: a 10th-90th percentile of the per-round
/// ratios rests on ten or more of them.
constexpr int kInterleavedRounds = 11;
/// Time `cases` (names of the plan's runs) over `rounds` interleaved rounds,
/// or read them from `<dir>/margins.json` when it holds exactly these cases,
/// rounds, plan and scene bytes; writes the file. Throws naming an unknown case.
Interleaved timeInterleaved(const Plan& plan, const std::vector<std::string>& cases, const std::string& dir, int rounds);

/// The runs a benchmark summary compares on one scene: per level, eigenmass's
/// fastest run and the two cheapest other owners' fastest runs, each once.
std::vector<std::string> benchmarkContenders(const std::vector<CaseRecord>& records, const std::string& scene, const BenchmarkSpec& spec);

/// A margin's interval: the median and the 10th and 90th percentiles of the
/// per-round ratios other / mine (> 1: mine cheaper); nullopt without rounds of both.
struct Margin {
  double median = 0, p10 = 0, p90 = 0;
  int rounds = 0;
};
std::optional<Margin> interleavedMargin(const Interleaved& t, const std::string& mine, const std::string& other);

/// eigenmass's fastest run at one accuracy (a benchmark level, an engine
/// study's accuracy) and the other owners' fastest runs there, cheapest by
/// their medians first: what a margin with its interval is measured on.
struct Contest {
  const CaseRecord* mine = nullptr;
  std::vector<std::pair<std::string, const CaseRecord*>> others;  ///< owner, run
};
/// How many of the cheapest other owners a margin is timed against: the next
/// owner by the consecutive repeats' medians may not be the next by the
/// interleaved rounds (issue 75 found the next owner changing between reruns).
constexpr size_t kContendersPerLevel = 2;
/// An owner this many times dearer than eigenmass by the medians is not timed
/// again: the margin is not in doubt, and rounds of it would cost the most (ODE's
/// 96 s runs on A02 at N = 40). Its interval is the extremes of the consecutive
/// repeats, other's min / eigenmass's max to other's max / eigenmass's min.
constexpr double kRetimeWithin = 10;
/// The runs of `c` to time in interleaved rounds (eigenmass's and the first
/// kContendersPerLevel others within kRetimeWithin), appended to `names` once each.
void addContenders(const Contest& c, std::vector<std::string>& names);
/// The margin of `other` over `mine`: from the interleaved rounds, else (an
/// owner kRetimeWithin dearer) from the consecutive repeats' extremes.
std::optional<Margin> contestMargin(const Interleaved& t, const CaseRecord& mine, const CaseRecord& other);
/// The verdict from the interleaved rounds: "met" when every contender's 10th
/// percentile ratio exceeds 1, "missed" when one's 90th falls below 1, else
/// "tied"; the nearest contender is named with its interval. c.mine must be set.
std::string marginVerdict(const Contest& c, const Interleaved& t);

/// One benchmark problem's merged results, for the summary across problems.
struct BenchmarkProblem {
  std::string scene;  ///< the scene's stem, as its records name it
  BenchmarkSpec spec;
  std::vector<CaseRecord> records;
  bool complete = true;  ///< every case has a result (else no goal is judged)
  Interleaved interleaved;  ///< the contenders' interleaved timings (none: the verdicts say so)
};
/// Per problem and level: each owner's fastest CPU, eigenmass's route, and whether it is the cheapest.
std::string benchmarkSummary(const std::vector<BenchmarkProblem>& problems);

/// CPU time at which a line (points in setting order, coarse to fine) first
/// reaches `target` error, interpolated log-log between the two points that
/// bracket it; nullopt if no point reaches it; the first point's time if it
/// already does (`at_first` set).
std::optional<double> timeToReach(const std::vector<double>& cpu, const std::vector<double>& err, double target,
                                  bool& at_first);

/// Least-squares slope of log y against log x (nullopt for fewer than 2 points).
std::optional<double> logSlope(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace em
