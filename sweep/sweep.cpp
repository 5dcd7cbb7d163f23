#include "sweep/sweep.hpp"
#include "solver/mechanism/formulation.hpp"

#include <sys/wait.h>
#include <csignal>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>

#include "compare/benchmark.hpp"
#include "io/digest.hpp"
#include "io/json_input.hpp"
#include "compare/lyapunov.hpp"
#include "compare/momenta.hpp"
#include "compare/progress.hpp"
#include "compare/provenance.hpp"
#include "compare/report.hpp"
#include "compare/sensitivity.hpp"
#include "solver/mechanism/assembly.hpp"
#include "solver/perturb.hpp"
#include "io/atomic_file.hpp"
#include "io/csv.hpp"
#include "io/digest.hpp"
#include "io/json_input.hpp"
#include "io/trajectory_json.hpp"

namespace em {

using json = nlohmann::json;
namespace fs = std::filesystem;

std::string caseFile(const std::string& dir, const SweepCase& c) { return (fs::path(dir) / (c.name + ".json")).string(); }
std::string caseCsv(const std::string& dir, const SweepCase& c) { return (fs::path(dir) / (c.name + ".csv")).string(); }

namespace {

json specKey(const RunSpec& s) {
  return {{"method", methodName(s.method)}, {"integrator", integratorName(s.integrator)}, {"setting", s.setting()}};
}

// A run's key, with the formulation that names the case (absent otherwise: older results stay valid).
json runKey(const SweepCase& c) {
  json k = specKey(c.spec);
  if (c.formulation_named) k["formulation"] = formulationName(c.spec->options.loops.formulation);
  if (!c.tuning.empty()) k["tuning"] = c.tuning;  // absent otherwise: older results stay valid
  return k;
}

// What a result file must have been made from to count for this plan: the
// scene's bytes, the grid, the run, the reference, the repeats.
json caseKey(const Plan& plan, const SweepCase& c, const std::string& scene_sha256) {
  json key = {{"case", c.name},
              {"scene_sha256", scene_sha256},
              {"t_end", plan.t_end},
              {"output_dt", plan.output_dt},
              {"repeats", c.role == CaseRole::Run ? plan.repeats : 1},
              {"max_steps", plan.options.max_steps},
              {"run", runKey(c)},
              {"reference", plan.reference ? specKey(*plan.reference) : json()}};
  const UrdfOptions& urdf = plan.scenes[c.scene].urdf;
  if (urdf.any())  // a URDF's import options make another model from the same bytes
  {
    key["scene_import"] = {{"balance_inertia", urdf.balance_inertia}, {"lock_joint", urdf.lock_joints},
                           {"floating_base", urdf.floating_base}};
    // The joint dynamics' options only when set: older results stay valid. A control file by its bytes.
    json& imp = key["scene_import"];
    if (urdf.damping) imp["damping"] = true;
    if (urdf.ignore_friction) imp["ignore_friction"] = true;
    if (urdf.limits_restitution) imp["limits_restitution"] = *urdf.limits_restitution;
    if (!urdf.control_file.empty()) imp["control_sha256"] = sha256Hex(readFile(urdf.control_file, "control file"));
  }
  if (const std::optional<StartOffset>& o = plan.scenes[c.scene].start_offset)  // absent without one
    key["start_offset"] = {{"q", o->q}, {"u", o->u}, {"seed", o->seed}};
  if (plan.ensemble) {  // absent without one: older results stay valid
    const Ensemble& e = *plan.ensemble;
    key["ensemble"] = {{"count", e.count}, {"seed", e.seed}, {"q", e.sigma_q}, {"u", e.sigma_u}};
    key["member"] = c.member;
  }
  // A method option only when set away from its fallback: older results stay valid.
  for (const MethodParam& m : methodParams()) {
    const auto set = plan.options.params.find(m.name);
    if (set != plan.options.params.end() && set->second != m.fallback)
      key[m.name] = m.whole ? json(static_cast<long>(set->second)) : json(set->second);
  }
  return key;
}

// A case result file (its syntax errors name it).
json readCaseFile(const std::string& path) { return readJsonFile(path, "case result"); }

// The file exists: it must have the key; throws naming it otherwise.
void checkKey(const std::string& path, const json& key) {
  json doc;
  try {
    doc = readCaseFile(path);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": unreadable case result (" + e.what() + "); remove it to run the case again");
  }
  const json theirs = doc.is_object() ? doc.value("key", json()) : json();
  if (theirs == key) return;
  // Name the first field that differs, both values cut short: one line, not two whole keys.
  std::string field = "key", was = printable(theirs.dump(), 60), now = printable(key.dump(), 60);
  if (theirs.is_object())
    for (const auto& [name, value] : key.items())
      if (!theirs.contains(name) || theirs[name] != value) {
        field = name;
        was = theirs.contains(name) ? printable(theirs[name].dump(), 60) : "absent";
        now = printable(value.dump(), 60);
        break;
      }
  throw std::runtime_error(path + ": made by another plan, scene file or version (its " + field + " is " + was +
                           ", this plan's " + now + "); use another --results folder or remove the file");
}

// The scene's (the member's) reference run: read from its case file, or run and written now.
Trajectory loadReference(const Plan& plan, const SweepCase& c, const Scene& scene, const std::string& dir) {
  const SweepCase r = referenceCaseOf(plan, c);
  const std::string path = caseFile(dir, r);
  if (!fs::exists(path)) runCase(plan, r, dir);
  checkKey(path, caseKey(plan, r, scene.source.sha256));
  return trajectoryFromJson(readCaseFile(path).at("trajectory"), r.spec, path);
}

CaseRecord baseRecord(const SweepCase& c, const Scene& scene) {
  CaseRecord rec;
  rec.name = c.name;
  rec.role = c.role;
  rec.scene = c.scene_name;
  rec.method = methodName(c.spec->method);
  rec.integrator = integratorName(c.spec->integrator);
  rec.setting_kind = c.spec->settingKind();
  rec.setting = c.spec->setting();
  rec.nu = scene.model.nu;
  rec.member = c.member;
  if (c.formulation_named) rec.formulation = formulationName(c.spec->options.loops.formulation);
  rec.tuning = c.tuning;
  return rec;
}

// Status, errors (against `ref` when given) and cost of the first repeat;
// the early error level up to t0.
void measure(CaseRecord& rec, const Model& model, const Trajectory& run, const Trajectory* ref, double t0,
             const std::optional<BenchmarkSpec>& benchmark) {
  rec.status = run.status();
  rec.failure = run.failure;
  rec.failure_kind = run.failure_kind;
  if (run.failed()) rec.failure_time = run.failure_time;
  rec.steps = run.steps;
  rec.rhs_evals = run.rhs_evals;
  rec.grid_cut_steps = gridCutSteps(run, run.run);
  if (info(run.run.method).eigenfactor) rec.eigen = run.eigen;
  const Trajectory& against = ref ? *ref : run;
  const MethodMetrics m = measureRun(run, against, {kCaseThresholds.begin(), kCaseThresholds.end()},
                                     std::vector<std::optional<double>>(kCaseThresholds.size()), energyScale(against));
  rec.has_error = ref != nullptr;
  rec.max_pose = m.pose.value;
  rec.max_coord = m.coords_shared ? m.coord.value : NAN;
  rec.max_energy = m.energy.value;
  if (const std::optional<MomentumDrift> d = momentumDrift(model, run)) rec.momentum_p = d->p, rec.momentum_H = d->H;
  if (std::isfinite(run.max_joint_separation)) rec.joint_separation = run.max_joint_separation;
  if (run.has_loops) {
    rec.loop_position_m = run.loops.position_m, rec.loop_position_rad = run.loops.position_rad;
    rec.loop_velocity_m = run.loops.velocity_m, rec.loop_velocity_rad = run.loops.velocity_rad;
  }
  // The benchmark error: against the problem's solution where it states one (every case, the
  // reference and its check included), else against the reference run.
  if (benchmark && (benchmark->hasSolution() || ref)) {
    const BenchmarkError b = benchmark->hasSolution() ? solutionError(*benchmark, run) : benchmarkError(*benchmark, run, *ref);
    // A run that failed before its first output step measured nothing: no error, not 0 (issue 73, item 14:
    // such runs were listed at error 0 and drawn at 1e-16).
    if (b.steps > 0) rec.benchmark_error = b.max_abs, rec.benchmark_error_t = b.at_t;
  }
  if (!ref) return;
  for (size_t i = 0; i < kCaseThresholds.size(); ++i) rec.pose_beyond[i] = m.divergence_time_s[i];
  double early = 0;
  for (size_t i = 0; i < m.series.t.size() && m.series.t[i] <= t0 * (1 + 1e-12); ++i) early = std::max(early, m.series.pose_rad[i]);
  rec.t0 = t0, rec.pose_by_t0 = early;
  if (m.coords_shared)
    for (size_t i = 0; i < kCaseThresholds.size(); ++i) rec.coord_beyond[i] = m.coord_divergence_time_s[i];
}

// A member's initial state as its case files record it: q0 and u0 in the scene's order, by name.
json memberJson(const Model& m, int member) {
  Eigen::VectorXd q, u;
  m.qToFile(m.q0(), q);
  m.uToFile(m.u0(), u);
  json j = {{"index", member}, {"q0", json::object()}, {"u0", json::object()}};
  const std::vector<std::string> qn = m.qNames(), un = m.uNames();
  for (int i = 0; i < m.nq; ++i) j["q0"][qn[i]] = q[i];
  for (int i = 0; i < m.nu; ++i) j["u0"][un[i]] = u[i];
  return j;
}

// The model a case runs: the scene's, its start displaced by the plan's
// start_offset, then the ensemble member's perturbation on top. On a
// mechanism a member's displaced start is assembled onto its loops (q0 onto
// g = 0, then u0 onto G u = 0, as --assemble does; issue 73, item 6: members
// ran "ok" from loops 1.4e-3 m open), and `assembled` says by how much.
Model caseModel(const Plan& plan, const SweepCase& c, const Scene& scene, std::optional<Assembly>* assembled = nullptr) {
  Model m = scene.model;
  if (const std::optional<StartOffset>& o = plan.scenes[c.scene].start_offset) m = perturbedStart(m, o->q, o->u, o->seed);
  if (!plan.ensemble || c.member == 0) return m;
  m = ensembleMember(m, *plan.ensemble, c.member);
  if (m.loops.empty()) return m;
  Assembly a;
  try {
    a = assembledStart(m, "member's drawn start");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(c.name + ": " + e.what() + ": a smaller ensemble.perturb.q keeps members nearer");
  }
  if (assembled) *assembled = a;
  return withInitialState(std::move(m), a.q, a.u);
}

bool sameEnd(const Trajectory& a, const Trajectory& b) {
  return a.size() == b.size() && a.failure_kind == b.failure_kind && (a.size() == 0 || (a.q.back() == b.q.back() && a.u.back() == b.u.back()));
}

}  // namespace

namespace {

// The case's file exists and has the key of this plan and scene bytes (throws if it has another).
bool doneWith(const Plan& plan, const SweepCase& c, const std::string& dir, const std::string& scene_sha256) {
  const std::string path = caseFile(dir, c);
  if (!fs::exists(path)) return false;
  checkKey(path, caseKey(plan, c, scene_sha256));
  return true;
}

}  // namespace

bool caseDone(const Plan& plan, const SweepCase& c, const std::string& dir) {
  // The key needs only the scene file's hash: no need to build its model.
  return doneWith(plan, c, dir, sha256Hex(readFile(plan.scenes[c.scene].file, "scene")));
}

bool runCase(const Plan& plan, const SweepCase& c, const std::string& dir) {
  const PlanScene& entry = plan.scenes[c.scene];
  const Scene scene = loadScene(entry.file, entry.urdf);
  if (doneWith(plan, c, dir, scene.source.sha256)) return false;
  CaseRecord rec = baseRecord(c, scene);
  json doc = {{"format", "eigenmass-sweep-case/1"}, {"plan", plan.name}, {"key", caseKey(plan, c, scene.source.sha256)}};
  doc["tables"] = json::array();  // the plan's tables: what plot draws from the merged results (outside the key)
  for (PlanTable t : plan.tables) doc["tables"].push_back(planTableName(t));
  if (plan.ensemble && plan.ensemble->claim) doc["claim"] = {{"t_s", plan.ensemble->claim->t_s}, {"label", plan.ensemble->claim->label}};
  std::optional<Assembly> assembled;
  const Model model = caseModel(plan, c, scene, &assembled);
  if (plan.ensemble) doc["member"] = memberJson(model, c.member);
  if (assembled)  // the drawn start's gaps and how far the assembly moved it (m or rad, m/s or rad/s)
    doc["member"]["assembly"] = {{"gap", assembled->gap}, {"velocity_gap", assembled->velocity_gap}, {"moved_q", assembled->moved_q},
                                 {"moved_u", assembled->moved_u}, {"iterations", assembled->iterations}};
  if (plan.scenes[c.scene].start_offset) {  // the displaced start, by name
    doc["start"] = memberJson(model, 0);
    doc["start"].erase("index");
  }
  const int repeats = c.role == CaseRole::Run ? plan.repeats : 1;
  std::optional<Trajectory> ref;
  if (plan.reference && c.role != CaseRole::Reference) ref = loadReference(plan, c, scene, dir);
  Trajectory first = runTrajectory(model, c.spec);
  rec.cpu_s.push_back(first.run_time_s);
  for (int k = 1; k < repeats; ++k) {
    const Trajectory again = runTrajectory(model, c.spec);
    rec.cpu_s.push_back(again.run_time_s);
    rec.repeats_identical = rec.repeats_identical && sameEnd(first, again);
  }
  measure(rec, scene.model, first, ref ? &*ref : nullptr, plan.t_end / 10,
          plan.hasTable(PlanTable::Benchmark) ? scene.benchmark : std::nullopt);
  // The member's exponent, for the prediction of divergence times (a benchmark predicts none: its levels are the subject).
  if (c.role == CaseRole::Reference && !plan.hasTable(PlanTable::Benchmark)) {
    LyapunovOptions lo;
    lo.t_end = plan.t_end;
    const Lyapunov l = lyapunovExponent(model, lo);
    rec.lyapunov_per_s = l.per_s, rec.lyapunov_uncertainty_per_s = l.uncertainty_per_s;
  }
  if (c.role == CaseRole::Reference)
    if (const std::optional<Sensitivity> twin = sensitivityTwin(model, c.spec, first)) {
      rec.sensitivity_rad = twin->max_pose_rad;
      rec.sensitivity_failed_at = twin->failed_at;
    }
  if (c.role == CaseRole::Reference) doc["trajectory"] = trajectoryJson(first);
  if (c.role == CaseRole::Run && plan.hasTable(PlanTable::Trajectories)) writeCsv(first, caseCsv(dir, c));
  doc["result"] = caseRecordJson(rec);
  doc["scene_source"] = sceneSourceJson(scene.source);  // as simulate's sidecar: the file, and an assembled start's move
  doc["provenance"] = provenance();
  writeJsonAtomic(doc, caseFile(dir, c));
  return true;
}

Interleaved timeInterleaved(const Plan& plan, const std::vector<std::string>& names, const std::string& dir, int rounds) {
  std::vector<SweepCase> cases;
  const std::vector<SweepCase> all = planCases(plan);
  for (const std::string& n : names) {
    const auto it = std::find_if(all.begin(), all.end(), [&](const SweepCase& c) { return c.name == n && c.role == CaseRole::Run; });
    if (it == all.end()) throw std::invalid_argument("interleaved timing: no run named " + printable(n, 80) + " in plan " + plan.name);
    cases.push_back(*it);
  }
  // What the file must have been made from: these cases' keys (plan, scene bytes, run), the rounds.
  json key = {{"rounds", rounds}, {"cases", json::array()}};
  std::vector<Scene> scenes;  // per case: its scene, read once per file
  std::map<size_t, size_t> scene_of;
  for (const SweepCase& c : cases) {
    if (!scene_of.count(c.scene)) {
      scene_of[c.scene] = scenes.size();
      scenes.push_back(loadScene(plan.scenes[c.scene].file, plan.scenes[c.scene].urdf));
    }
    key["cases"].push_back(caseKey(plan, c, scenes[scene_of[c.scene]].source.sha256));
  }
  const std::string path = (fs::path(dir) / "margins.json").string();
  Interleaved out;
  out.rounds = rounds;
  if (fs::exists(path)) {
    const json doc = readJsonFile(path, "interleaved timings");
    if (doc.is_object() && doc.value("key", json()) == key) {
      for (const SweepCase& c : cases) out.cpu_s[c.name] = doc.at("cpu_s").at(c.name).get<std::vector<double>>();
      return out;
    }
  }
  std::vector<Model> models;
  for (const SweepCase& c : cases) models.push_back(caseModel(plan, c, scenes[scene_of[c.scene]]));
  for (int k = 0; k < rounds; ++k)
    for (size_t i = 0; i < cases.size(); ++i) out.cpu_s[cases[i].name].push_back(runTrajectory(models[i], cases[i].spec).run_time_s);
  json doc = {{"format", "eigenmass-margins/1"}, {"plan", plan.name}, {"key", key}, {"cpu_s", out.cpu_s}, {"provenance", provenance()}};
  writeJsonAtomic(doc, path);  // replaces a file made from other cases: it is this folder's own
  return out;
}

std::optional<Margin> interleavedMargin(const Interleaved& t, const std::string& mine, const std::string& other) {
  const auto a = t.cpu_s.find(mine), b = t.cpu_s.find(other);
  if (a == t.cpu_s.end() || b == t.cpu_s.end() || a->second.size() != b->second.size() || a->second.empty()) return std::nullopt;
  std::vector<double> ratios;
  for (size_t k = 0; k < a->second.size(); ++k) ratios.push_back(b->second[k] / a->second[k]);
  return Margin{*quantile(ratios, 0.5), *quantile(ratios, 0.1), *quantile(ratios, 0.9), static_cast<int>(ratios.size())};
}

// The margin of `other` over `mine`: from the interleaved rounds, else (an owner
// kRetimeWithin dearer, or no rounds) from the consecutive repeats' extremes.
std::optional<Margin> contestMargin(const Interleaved& t, const CaseRecord& mine, const CaseRecord& other) {
  if (std::optional<Margin> m = interleavedMargin(t, mine.name, other.name)) return m;
  if (other.cpuMedian() <= kRetimeWithin * mine.cpuMedian() || mine.cpu_s.empty() || other.cpu_s.empty()) return std::nullopt;
  return Margin{other.cpuMedian() / mine.cpuMedian(), other.cpuMin() / mine.cpuMax(), other.cpuMax() / mine.cpuMin(), 0};
}

// The summary's verdict from the interleaved rounds: met when every contender's
// 10th percentile ratio exceeds 1, missed when one's 90th falls below 1, else
// tied; the nearest contender is named with its interval.
std::string marginVerdict(const Contest& cell, const Interleaved& t) {
  if (cell.others.empty()) return "met (no other owner reached it)";
  std::string nearest_owner;
  std::optional<Margin> nearest;
  bool missed = false, tied = false;
  for (size_t i = 0; i < cell.others.size() && i < kContendersPerLevel; ++i) {
    const std::optional<Margin> m = contestMargin(t, *cell.mine, *cell.others[i].second);
    if (!m) {  // no interleaved rounds: the medians' ratio, said to have no interval
      const double r = cell.others[0].second->cpuMedian() / cell.mine->cpuMedian();
      return std::string(r > 1 ? "met" : "missed") + " (no interval: not timed interleaved): next " + cell.others[0].first + " " +
             gnum(r > 1 ? r : 1 / r, 3) + "x " + (r > 1 ? "dearer" : "cheaper");
    }
    missed = missed || m->p90 < 1;
    tied = tied || (m->p10 <= 1 && m->p90 >= 1);
    if (!nearest || m->median < nearest->median) nearest = m, nearest_owner = cell.others[i].first;
  }
  const std::string interval = " [" + gnum(nearest->p10, 3) + ", " + gnum(nearest->p90, 3) + "]";
  if (missed) return "missed: " + nearest_owner + " " + gnum(1 / nearest->median, 3) + "x cheaper (ratio " + gnum(nearest->median, 3) + interval + ")";
  if (tied) return "tied: " + nearest_owner + " " + gnum(nearest->median, 3) + "x" + interval;
  return "met: next " + nearest_owner + " " + gnum(nearest->median, 3) + "x dearer" + interval;
}


void addContenders(const Contest& c, std::vector<std::string>& names) {
  auto add = [&](const CaseRecord* r) {
    if (r && std::find(names.begin(), names.end(), r->name) == names.end()) names.push_back(r->name);
  };
  if (!c.mine) return;
  add(c.mine);
  for (size_t i = 0; i < c.others.size() && i < kContendersPerLevel; ++i)
    if (c.others[i].second->cpuMedian() <= kRetimeWithin * c.mine->cpuMedian()) add(c.others[i].second);
}

std::vector<std::string> listCommands(const Plan& plan, const std::string& plan_path, const std::string& dir) {
  auto quoted = [](const std::string& s) {
    std::string q = "'";
    for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return q + "'";
  };
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const std::string program = ec ? "eigenmass" : exe.string();
  std::vector<std::string> out;
  for (const SweepCase& c : planCases(plan))
    out.push_back(quoted(program) + " sweep " + quoted(fs::absolute(plan_path).string()) + " --case " + quoted(c.name) +
                  " --results " + quoted(fs::absolute(dir).string()));
  return out;
}

namespace {

// Cases done / total, elapsed, time left: a line every kProgressLineS once the
// sweep has run kProgressAfterS, at the end, and at once for every failed case.
class SweepProgress {
 public:
  SweepProgress(size_t total, size_t done) : total_(total), done_(done), start_done_(done) {}
  void finished(const std::string& what) {
    ++done_;
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const double left = elapsed / static_cast<double>(done_ - start_done_) * static_cast<double>(total_ - done_);
    const bool quiet = elapsed < kProgressAfterS || elapsed - last_line_ < kProgressLineS;
    if (what.empty() && ((quiet && done_ < total_) || progressMode() == ProgressMode::Off)) return;  // --no-progress: failures only
    last_line_ = elapsed;
    std::fprintf(stderr, "sweep: %zu / %zu cases, elapsed %.0f s, ETA %.0f s%s%s\n", done_, total_, elapsed, left,
                 what.empty() ? "" : ": ", what.c_str());
  }

 private:
  using Clock = std::chrono::steady_clock;
  size_t total_, done_, start_done_;
  Clock::time_point start_ = Clock::now();
  double last_line_ = 0;  ///< elapsed s at the last line
};

// Run one case in a child process: its CPU clock is its own, a crash is its own.
// It dies with the parent (dieWithParent: SIGTERM, which removes its temporary),
// and the parent's interrupt ends and reaps it (endOnInterrupt): never an orphan.
pid_t startCase(const Plan& plan, const SweepCase& c, const std::string& dir) {
  std::fflush(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("cannot start a worker process");
  if (pid > 0) {
    endOnInterrupt(pid);
    return pid;
  }
  if (!dieWithParent(parent, SIGTERM)) _exit(143);
  int code = 0;
  try {
    setProgressMode(ProgressMode::Off);
    runCase(plan, c, dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sweep: case %s: %s\n", c.name.c_str(), e.what());
    code = 1;
  }
  std::fflush(nullptr);
  _exit(code);
}

// What the finished case's file says, for the progress line ("" when it ran to the end).
std::string failureNote(const SweepCase& c, const std::string& dir, int wstatus) {
  if (WIFSIGNALED(wstatus))
    return c.name + " could not be run: its worker was killed by signal " + std::to_string(WTERMSIG(wstatus)) + " (" +
           strsignal(WTERMSIG(wstatus)) + ")";
  if (!WIFEXITED(wstatus) || WEXITSTATUS(wstatus) != 0) return c.name + " could not be run (its error above)";
  const CaseRecord r = readCaseRecord(readCaseFile(caseFile(dir, c)).at("result"), caseFile(dir, c));
  if (r.status == Outcome::Ok) return "";
  return c.name + " failed at " + gnum(r.failure_time.value_or(0), 4) + " s (" + failureName(r.failure_kind) + ")";
}

// Run `todo` on `jobs` worker processes; returns how many could not be run.
int runPool(const Plan& plan, const std::vector<SweepCase>& todo, const std::string& dir, int jobs, SweepProgress& meter) {
  std::map<pid_t, const SweepCase*> running;
  size_t next = 0;
  int errors = 0;
  while (next < todo.size() || !running.empty()) {
    while (next < todo.size() && static_cast<int>(running.size()) < jobs) {
      running[startCase(plan, todo[next], dir)] = &todo[next];
      ++next;
    }
    int wstatus = 0;
    const pid_t pid = waitpid(-1, &wstatus, 0);
    if (pid < 0) throw std::runtime_error("lost a worker process");
    releaseOnInterrupt(pid);
    const SweepCase* c = running.at(pid);
    running.erase(pid);
    if (!WIFEXITED(wstatus) || WEXITSTATUS(wstatus) != 0) ++errors;
    meter.finished(failureNote(*c, dir, wstatus));
  }
  return errors;
}

}  // namespace

int runSweep(const Plan& plan, const std::string& dir, int jobs) {
  const std::vector<SweepCase> cases = planCases(plan);
  std::vector<SweepCase> references, runs;
  for (const SweepCase& c : cases) {
    if (caseDone(plan, c, dir)) continue;
    (c.role == CaseRole::Reference ? references : runs).push_back(c);
  }
  SweepProgress meter(cases.size(), cases.size() - references.size() - runs.size());
  if (references.size() + runs.size() < cases.size())
    std::fprintf(stderr, "sweep: %zu of %zu cases already have a result in %s\n", cases.size() - references.size() - runs.size(),
                 cases.size(), dir.c_str());
  int errors = runPool(plan, references, dir, jobs, meter);
  errors += runPool(plan, runs, dir, jobs, meter);
  return errors;
}

}  // namespace em
