#include "compare/comparison.hpp"

#include "reference/engine.hpp"
#include "solver/integrate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace em {

CompareOptions::CompareOptions() : reference(defaultReferenceSpec()) {
  for (const MethodInfo& m : methodTable())
    if (!m.retired) methods.push_back(m.id);
  inhouse.method = Method::Classical;
  inhouse.integrator = defaultIntegrator(Engine::InHouse);
  for (Engine e : otherEngines()) {
    RunSpec& s = engines[e];
    s.method = info(e).method;
    s.integrator = defaultIntegrator(e);
    s.tol = kEngineTol;
  }
}

void CompareOptions::chooseIntegrator(Engine e, Integrator i) {
  engines.at(e).integrator = i;
  chosen.insert(e);
}

RunSpec CompareOptions::specFor(Method method) const {
  const Engine e = info(method).engine;
  RunSpec s = e == Engine::InHouse ? inhouse : engines.at(e);
  if (e != Engine::InHouse && followsInHouse(e)) {  // the in-house step, and its scheme where the engine has it
    if (!chosen.count(e)) s.integrator = info(inhouse.integrator).runs(e) ? inhouse.integrator : defaultIntegrator(e);
    s.dt = inhouse.dt;
  }
  s.method = method;
  return s;
}

std::vector<RunSpec*> CompareOptions::allSpecs() {
  std::vector<RunSpec*> all = {&inhouse, &reference};
  for (auto& [e, s] : engines) all.push_back(&s);
  return all;
}

bool followsInHouse(Engine e) { return info(defaultIntegrator(e)).fixed_step; }

void CompareOptions::useMechanismReference(const Model& m) {
  if (!m.limited.empty()) {  // joint limits: the in-house exact events (docs/theory.md §17), which no engine's stop is
    const double tol = reference.tol;
    reference = defaultReferenceSpec(Method::Classical);
    reference.tol = tol;
    return;
  }
  if (!m.isMechanism()) return;
  const double tol = reference.tol;
  reference = defaultReferenceSpec(Method::Classical);
  reference.tol = tol;
  reference.integrator = Integrator::IDA;
  mechanism_reference = true;
}

void refuseUnreadInHouseSettings(const CompareOptions& o, const AskedInHouse& asked) {
  bool inhouse = false, follows_dt = false, follows_scheme = false;
  for (Method m : o.methods) {
    const Engine e = info(m).engine;
    if (e == Engine::InHouse) inhouse = true;
    else if (followsInHouse(e)) follows_dt = true, follows_scheme = follows_scheme || info(o.inhouse.integrator).runs(e);
  }
  if (inhouse) return;
  const std::string dash = o.keywords ? "" : "--";
  const auto refuse = [&](bool given, const char* option, const char* what) {
    if (given) throw std::invalid_argument(dash + option + ": " + what + ", and none is among " + dash + "methods");
  };
  refuse(asked.tol, "tol", "it sets the in-house methods' tolerance");
  if (!follows_dt) refuse(asked.dt, "dt", "it sets the step of the in-house methods and of a fixed-step engine");
  if (!follows_scheme)
    refuse(asked.integrator, "integrator", "it sets the in-house methods' scheme (and a fixed-step engine's where it has it)");
}

void CompareOptions::leaveOutRefused(const Model& m) {
  std::vector<Method> kept;
  for (Method method : methods) {
    const std::string why = methodRefusal(method, m);
    if (why.empty()) kept.push_back(method);
    else left_out.emplace_back(method, why);
  }
  methods = kept;
}

void CompareOptions::leaveOutUnrunnable(const Model& m, bool named) {
  std::vector<Method> kept;
  for (Method method : methods) {
    RunSpec s = inhouse;
    s.method = method;
    try {
      if (info(method).engine == Engine::InHouse) refuseUnrunnable(m, s);
      kept.push_back(method);
    } catch (const std::invalid_argument& e) {
      if (named) throw;
      left_out.emplace_back(method, e.what());
    }
  }
  methods = kept;
}

ComparisonResult compareTrajectories(const Trajectory& reference, const Trajectory& tight, std::vector<Trajectory> runs,
                             const CompareOptions& opt) {
  ComparisonResult r;
  r.options = opt;
  r.t_end = reference.run.t_end;
  r.output_dt = reference.run.output_dt;
  r.reference = reference;
  r.tight = tight;
  r.horizon = referenceHorizon(reference, tight, opt.thresholds);
  const EnergyScale scale = energyScaleOf(reference);
  for (double e : errorSeries(reference, tight, scale.joules).pose_rad) r.reference_check_pose_rad = std::max(r.reference_check_pose_rad, e);
  r.energy_scale = scale.joules;
  r.energy_scale_definition = scale.definition;
  r.reference_metrics = measureRun(reference, reference, opt.thresholds, r.horizon, r.energy_scale);
  r.runs = std::move(runs);
  for (const Trajectory& t : r.runs) r.metrics.push_back(measureRun(t, reference, opt.thresholds, r.horizon, r.energy_scale));
  const std::optional<double> wrong_horizon = referenceHorizon(reference, tight, {kWrongRad})[0];
  for (MethodMetrics& m : r.metrics) m.outcome = outcomeOf(m, wrong_horizon);
  r.reference_metrics.outcome = reference.status();
  return r;
}

namespace {

// The command-line option behind a refused setting of run i (the reference
// and its tighter twin first, then the methods): what the user typed.
std::string settingOption(const SettingError& e, size_t i, const RunSpec& s, bool keywords) {
  if (keywords) return e.field;  // the Python module's keyword (t_end, dt): the reference's settings are not asked there
  if (i < 2) return e.option("reference-");
  // Another engine's tolerance is its own option (--simbody-tol); a step follows --dt.
  return e.option(s.engine() != Engine::InHouse && e.field == "tol" ? std::string(engineName(s.engine())) + "-" : "");
}

// Everything that can be refused is refused here, before the reference runs:
// the specs come back checked, the only form a run takes.
std::vector<CheckedRunSpec> checkComparison(const Model& m, const CompareOptions& opt, const std::vector<RunSpec>& specs) {
  if (opt.thresholds.empty()) throw std::invalid_argument("at least one threshold is needed");
  // An option as the caller typed it: the CLI's --name or the module's keyword.
  const auto named = [&](std::string kw) {
    if (opt.keywords) return kw;
    for (char& c : kw) c = c == '_' ? '-' : c;
    return "--" + kw;
  };
  if (opt.lyapunov_starts < 1 || opt.lyapunov_starts > kLyapunovStartsMax)
    throw std::invalid_argument(named("lyapunov_starts") + ": from 1 to " + std::to_string(kLyapunovStartsMax) + ", got " +
                                std::to_string(opt.lyapunov_starts));
  if (opt.lyapunov_starts > 1 && !(opt.lyapunov_long_s > 0))
    throw std::invalid_argument(named("lyapunov_starts") + ": needs " + named("lyapunov_long"));
  if (opt.lyapunov_starts > 1 && !m.loops.empty())
    throw std::invalid_argument(named("lyapunov_starts") + ": scene '" + m.name + "' has loops, which displaced starts would open");
  if (!(opt.lyapunov_sigma > 0 && opt.lyapunov_sigma <= 0.1))
    throw std::invalid_argument(named("lyapunov_sigma") + ": must be in (0, 0.1], got " + gnum(opt.lyapunov_sigma));
  for (const RunSpec& s : specs) requireRunnable(s, m);  // a joint kind it lacks, a setting it would not run as asked: named, before any run
  for (double th : opt.thresholds)
    if (!(th > 0)) throw std::invalid_argument("thresholds must be > 0");
  for (size_t i = 0; i < opt.methods.size(); ++i)
    if (std::count(opt.methods.begin(), opt.methods.begin() + i, opt.methods[i]))
      throw std::invalid_argument(std::string("method '") + methodName(opt.methods[i]) + "' is listed twice");
  std::vector<CheckedRunSpec> runs;
  for (size_t i = 0; i < specs.size(); ++i) {
    try {
      runs.push_back(checked(specs[i]));
    } catch (const SettingError& e) {
      throw e.as(settingOption(e, i, specs[i], opt.keywords));
    }
  }
  return runs;
}

}  // namespace

namespace {

// Every run of a comparison on the scene's grid: the reference, its tighter
// twin, then the methods in order.
std::vector<RunSpec> comparisonSpecs(const Scene& scene, const CompareOptions& opt) {
  const RunSpec ref_spec = onGrid(opt.reference, scene, opt.grid);
  RunSpec tight_spec = ref_spec;
  tight_spec.tol = ref_spec.tol / opt.tight_factor;
  std::vector<RunSpec> specs = {ref_spec, tight_spec};
  for (Method method : opt.methods) specs.push_back(onGrid(opt.specFor(method), scene, opt.grid));
  return specs;
}

Trajectory runLabelled(const Scene& scene, const CheckedRunSpec& s, const std::string& label,
                       void (*progress)(const std::string&)) {
  if (progress) progress(label);
  return runTrajectory(scene.model, s);
}

// The second engine (its row's roles: scheme and step; the output step if finer) on the reference's grid.
void runSecondEngine(const Scene& scene, const RunSpec& reference, ReferenceRuns& out, void (*progress)(const std::string&)) {
  const EngineInfo& second = info(secondEngine());
  if (!second.roles.second_scheme) {
    out.second_engine_skipped = "no engine's row names itself the second engine";
    return;
  }
  if (!scene.model.limited.empty()) {  // no engine's stop is an exact event: none checks the reference's impacts
    out.second_engine_skipped = "joint limits: no engine's stop is an exact event (docs/theory.md §17); the reference's twin checks it";
    return;
  }
  RunSpec s = reference;
  s.options.max_steps = HUGE_VAL;  // its cost is the floor's, asked for by the comparison
  std::string label;
  if (scene.model.isMechanism() && engineCode(second.id).soft_closures) {
    // Soft closures (MuJoCo's) are no check of a mechanism's reference: the
    // reference engine's exact constraints at the reference's tolerance are.
    const EngineInfo& exact = info(referenceEngine());
    s.method = exact.method;
    s.integrator = parseIntegrator(exact.adaptive_scheme);
    label = std::string(exact.name) + "/" + exact.adaptive_scheme + " (a mechanism: " + second.name + "'s closures are soft)";
  } else {
    s.method = second.method;
    s.integrator = parseIntegrator(second.roles.second_scheme);
    s.dt = reference.output_dt / std::ceil(reference.output_dt / second.roles.second_dt - 1e-9);
    label = std::string(second.name) + "/" + second.roles.second_scheme + " dt " + gnum(s.dt);
  }
  try {
    out.second_engine = runLabelled(scene, checked(s), "second engine " + label, progress);
  } catch (const std::exception& e) {
    out.second_engine_skipped = engineName(s.engine()) + std::string(": ") + e.what();  // the engine that was to run
  }
}

// A mechanism's default reference, IDA, stops at the first singular position
// (its index-2 rows lose rank there). The reference and its twin then run
// again under the index-3 augmented Lagrangian at penalty ratio 1e6
// (docs/theory.md eq. (M13)), which keeps the branch through singular
// positions and converges as its step falls. Its step follows the tolerance,
// h = (tol / 100)^(1/3) cut to divide the output step (the trapezoidal rule's
// local error is O(h^3); tol 1e-10: h = 1e-4), and its twin halves it, so the
// two differ by about half the reference's error or more (on A02, N = 2, over
// 20 s the error is first order in h through the passes: 2.6e-7, 1.3e-7,
// 6.5e-8 m at h = 2e-4, 1e-4, 5e-5; over 5 s on a row of three four-bars,
// second). The projection under rk8pd, the replacement until now, drifts off
// the branch's motion as its tolerance tightens (A02: 1.0e-2 m at 1e-10; fails
// at 1e-12). A scene the rule refuses (quaternion joints) keeps that route, and
// the note says which ran. IDA's run is kept as the check over IDA's span;
// where the replacement also stops, the comparison says so as for any failed
// reference.
constexpr double kReplacementPenaltyRatio = 1e6;
// The replacement's smallest step: below it the rule's error rises again (its
// Newton works at round-off; A02 over 20 s: 6.5e-8 m at h = 5e-5, 3.8e-7 at
// 2e-5; at 4.6e-6, 44 unconverged steps and an energy error of 6.7e-3).
constexpr double kReplacementMinStep = 5e-5;

// The replacement of `s` (the reference's spec); `halved`: its twin.
RunSpec replacementSpec(const RunSpec& s, bool trapezoidal, bool halved) {
  RunSpec r = s;
  if (trapezoidal) {
    r.integrator = Integrator::Trapezoidal;
    r.options.loops.formulation = Formulation::AugmentedLagrangian;
    r.options.loops.penalty_ratio = kReplacementPenaltyRatio;
    r.options.loops.alpha = r.options.loops.beta = 0;
    const double h = std::max(std::cbrt(s.tol / 100), kReplacementMinStep);
    r.dt = s.output_dt / std::ceil(s.output_dt / h - 1e-9) / (halved ? 2 : 1);
  } else {
    r.integrator = Integrator::RK8PD;
    r.options.loops.formulation = Formulation::Projection;
  }
  return r;
}

// The rule integrates q' = u: a ball or free joint's quaternion refuses it.
bool takesTrapezoidal(const Model& m) { return m.nq == m.nu; }

void replaceStoppedReference(const Scene& scene, const CompareOptions& opt, const std::vector<CheckedRunSpec>& specs,
                             ReferenceRuns& out, void (*progress)(const std::string&)) {
  if (!opt.mechanism_reference || !out.reference.failed() || !scene.model.isMechanism() || scene.model.loops.empty()) return;
  const bool al = takesTrapezoidal(scene.model);
  const std::string route = al ? "classical/trapezoidal with the augmented Lagrangian (penalty ratio 1e6, h = max((tol/100)^(1/3), " +
                                     gnum(kReplacementMinStep) + " s) = " + gnum(replacementSpec(specs[0].spec(), true, false).dt) + " s, its twin at h/2)"
                               : "classical/rk8pd with the projection at the same tolerances (the scene's ball or free joints refuse the augmented Lagrangian)";
  out.reference_note = "IDA ended at t = " + gnum(out.reference.failure_time) + " s (" + out.reference.failure +
                       "); the reference is " + route + ", which passes singular positions, checked against IDA over IDA's span";
  out.stopped = std::move(out.reference);
  out.reference = runLabelled(scene, checked(replacementSpec(specs[0].spec(), al, false)), "reference " + route + ": IDA ended early", progress);
  out.tight = runLabelled(scene, checked(al ? replacementSpec(specs[0].spec(), true, true) : replacementSpec(specs[1].spec(), false, false)),
                          "horizon run of the same route", progress);
  for (const Trajectory* t : {&out.reference, &out.tight})
    if (const long n = t->loops.newton_unconverged; n > 0)
      out.reference_note += "; its " + std::string(t == &out.reference ? "" : "twin's ") + "Newton stopped unconverged at " +
                            std::to_string(n) + " steps";
}

// The reference runs of checked specs (reference, its twin: specs[0], specs[1]).
ReferenceRuns referenceOf(const Scene& scene, const CompareOptions& opt, const std::vector<CheckedRunSpec>& specs,
                          void (*progress)(const std::string&)) {
  ReferenceRuns out{runLabelled(scene, specs[0], std::string("reference ") + methodName(specs[0]->method), progress),
                    runLabelled(scene, specs[1], "horizon run (tolerance / " + gnum(opt.tight_factor) + ")", progress), {}, {}, {}, {}, {}, {}, {}, {}};
  replaceStoppedReference(scene, opt, specs, out, progress);
  LyapunovOptions lo;
  lo.t_end = specs[0]->t_end;  // the grid's horizon
  out.lyapunov = lyapunovExponent(scene.model, lo);
  if (opt.lyapunov_long_s > 0) {
    if (progress) progress("long-run Lyapunov exponent over " + gnum(opt.lyapunov_long_s) + " s");
    LyapunovStarts st = lyapunovOverStarts(scene.model, longRunOptions(opt.lyapunov_long_s), opt.lyapunov_starts, opt.lyapunov_sigma);
    out.lyapunov_long = st.starts.front();  // the scene's own start
    if (opt.lyapunov_starts > 1) out.lyapunov_long_starts = std::move(st);
  }
  if (opt.sensitivity_twin) {
    if (progress && scene.model.loops.empty()) progress("sensitivity twin (the reference from a start " + gnum(kSensitivitySigma) + " away)");
    out.sensitivity = sensitivityTwin(scene.model, specs[0], out.reference);
  }
  if (opt.second_engine) runSecondEngine(scene, specs[0], out, progress);
  return out;
}

// The methods' runs of checked specs (specs[2...]) against the reference runs.
ComparisonResult compareAgainst(const Scene& scene, const CompareOptions& opt, const std::vector<CheckedRunSpec>& specs,
                                const ReferenceRuns& reference, void (*progress)(const std::string&)) {
  std::vector<Trajectory> runs;
  for (size_t i = 2; i < specs.size(); ++i) runs.push_back(runLabelled(scene, specs[i], methodName(specs[i]->method), progress));
  ComparisonResult r = compareTrajectories(reference.reference, reference.tight, std::move(runs), opt);
  const Model& m = scene.model;
  r.reference_metrics.tracking = trackingOf(m, r.reference);
  for (size_t i = 0; i < r.metrics.size(); ++i) r.metrics[i].tracking = trackingOf(m, r.runs[i]);
  if (!m.limited.empty())
    for (size_t i = 0; i < r.metrics.size(); ++i) r.metrics[i].impact_check = checkImpacts(r.runs[i], r.reference);
  r.scene_name = m.name;
  r.scene_source = scene.source;
  r.nq = m.nq;
  r.nu = m.nu;
  r.bodies = m.n();
  r.lyapunov = reference.lyapunov;
  r.lyapunov_long = reference.lyapunov_long;
  r.lyapunov_long_starts = reference.lyapunov_long_starts;
  r.sensitivity = reference.sensitivity;
  r.second_engine = reference.second_engine;
  r.second_engine_skipped = reference.second_engine_skipped;
  r.reference_note = reference.reference_note;
  if (reference.stopped) {
    r.stopped_reference = reference.stopped;
    // A check needs a sample past t = 0 (the start is the same by construction).
    if (reference.stopped->t.size() > 1)
      r.stopped_reference_metrics = measureRun(*reference.stopped, r.reference, opt.thresholds, r.horizon, r.energy_scale);
  }
  if (r.second_engine)
    r.second_engine_metrics = measureRun(*r.second_engine, r.reference, opt.thresholds, r.horizon, r.energy_scale);
  std::vector<Engine> ran = {r.reference.run.engine()};
  if (r.second_engine) ran.push_back(r.second_engine->run.engine());
  for (const Trajectory& t : r.runs) ran.push_back(t.run.engine());
  for (Engine e : ran) {
    const std::string note = engineSceneNote(e, m), name = engineName(e);
    const bool known = std::any_of(r.engine_notes.begin(), r.engine_notes.end(), [&](const auto& n) { return n.first == name; });
    if (!note.empty() && !known) r.engine_notes.emplace_back(name, note);
  }
  return r;
}

// Every run of the comparison on the scene's grid, checked once.
std::vector<CheckedRunSpec> checkedSpecs(const Scene& scene, const CompareOptions& opt) {
  return checkComparison(scene.model, opt, comparisonSpecs(scene, opt));
}

}  // namespace

void checkComparisonOptions(const Scene& scene, const CompareOptions& opt) { checkedSpecs(scene, opt); }

ReferenceRuns runReference(const Scene& scene, const CompareOptions& opt, void (*progress)(const std::string&)) {
  return referenceOf(scene, opt, checkedSpecs(scene, opt), progress);
}

ComparisonResult runComparison(const Scene& scene, const CompareOptions& opt, void (*progress)(const std::string&)) {
  const std::vector<CheckedRunSpec> specs = checkedSpecs(scene, opt);
  return compareAgainst(scene, opt, specs, referenceOf(scene, opt, specs, progress), progress);
}

ComparisonResult runComparison(const Scene& scene, const CompareOptions& opt, const ReferenceRuns& reference,
                               void (*progress)(const std::string&)) {
  return compareAgainst(scene, opt, checkedSpecs(scene, opt), reference, progress);
}

namespace {

std::string timeOrDash(const std::optional<double>& t, bool meaningful) {
  if (!t) return "-";
  char b[32];
  std::snprintf(b, sizeof b, "%.2f%s", *t, meaningful ? "" : "*");
  return b;
}

// A mechanism's table: one more column, how far each run's loops stood open
// (the larger of its position violations, m or rad, by eigenmass's g(q)).
bool anyLoops(const std::vector<MethodMetrics>& ms) {
  return std::any_of(ms.begin(), ms.end(), [](const MethodMetrics& m) { return m.has_loops; });
}

void tableHeader(std::ostream& o, const std::vector<double>& thresholds, bool loops) {
  char cell[64];
  std::snprintf(cell, sizeof cell, "%-18s %-7s", "method", "outcome");
  o << cell;
  for (const char* kind : {"pose", "joint"})
    for (double th : thresholds) {
      std::snprintf(cell, sizeof cell, " %12s", (std::string(kind) + ">" + gnum(th)).c_str());
      o << cell;
    }
  std::snprintf(cell, sizeof cell, " %12s %12s%s %10s %10s\n", "max pose rad", "max dE/Escl", loops ? "   loops open" : "", "steps",
                "CPU s");
  o << cell;
}

void tableRow(std::ostream& o, const MethodMetrics& m, bool loops) {
  char cell[64];
  std::snprintf(cell, sizeof cell, "%-18s %-7s", m.name().c_str(), outcomeName(m.outcome));
  o << cell;
  for (size_t i = 0; i < m.divergence_time_s.size(); ++i) {
    std::snprintf(cell, sizeof cell, " %12s", timeOrDash(m.divergence_time_s[i], m.divergence_meaningful[i]).c_str());
    o << cell;
  }
  for (const auto& t : m.coord_divergence_time_s) {
    std::snprintf(cell, sizeof cell, " %12s", timeOrDash(t, true).c_str());
    o << cell;
  }
  std::snprintf(cell, sizeof cell, " %12.3e %12.3e", m.pose.value, m.energy.value);
  o << cell;
  if (loops) {
    if (m.has_loops) std::snprintf(cell, sizeof cell, " %12.3e", std::max(m.loops.position_m, m.loops.position_rad));
    else std::snprintf(cell, sizeof cell, " %12s", "-");
    o << cell;
  }
  std::snprintf(cell, sizeof cell, " %10ld %10.3f\n", m.steps, m.run_time_s);
  o << cell;
}

void referenceLine(std::ostream& o, const ComparisonResult& r) {
  const Trajectory& ref = r.reference;
  o << "reference: " << ref.method() << "/" << ref.integrator() << " " << settingKindName(ref.run.settingKind()) << " "
    << gnum(ref.run.setting());
  if (ref.failed())
    o << " FAILED at t = " << gnum(ref.failure_time) << " s: " << ref.failure
      << " (errors are measured against its samples only)";
  o << "; horizon (reference vs its twin at " << settingKindName(r.tight.run.settingKind()) << " " << gnum(r.tight.run.setting()) << "):";
  for (size_t i = 0; i < r.horizon.size(); ++i)
    o << " " << gnum(r.options.thresholds[i]) << " rad " << (r.horizon[i] ? gnum(*r.horizon[i]) + " s" : "not within t_end");
  o << "; the two differ by at most " << gnum(r.reference_check_pose_rad, 3)
    << " rad: a method's error near or below that is the reference's as much as its own\n";
  if (r.stopped_reference_metrics)
    o << "reference: " << r.reference_note << ": IDA against it over [0, " << gnum(r.stopped_reference->failure_time)
      << "] s: max pose " << gnum(r.stopped_reference_metrics->pose.value, 3) << " rad\n";
  else if (r.stopped_reference)
    o << "reference: " << r.reference_note << ": IDA's span [0, " << gnum(r.stopped_reference->failure_time)
      << "] s holds no output sample after t = 0: not checked\n";
  if (r.second_engine_metrics) {
    const MethodMetrics& m = *r.second_engine_metrics;
    const RunSpec& run = r.second_engine->run;
    o << "second engine: " << r.second_engine->method() << "/" << r.second_engine->integrator() << " "
      << settingKindName(run.settingKind()) << " " << gnum(run.setting()) << " against the reference: max pose "
      << gnum(m.pose.value, 3) << " rad" << (r.second_engine->failed() ? " (FAILED at t = " + gnum(m.failure_time) + " s: over [0, " + gnum(m.failure_time) + "] s only)" : "")
      << ", the two independent engines' distance: errors below it are not resolved\n";
  } else if (!r.second_engine_skipped.empty()) {
    o << "second engine: not run (" << r.second_engine_skipped << ")\n";
  }
  if (const std::optional<Sensitivity>& s = r.sensitivity) {
    std::vector<std::string> ill;
    for (double th : r.options.thresholds)
      if (illConditioned(*s, th)) ill.push_back(gnum(th) + " rad");
    o << "sensitivity twin (the reference from a start " << gnum(s->sigma) << " away): "
      << (s->failed_at ? "stopped at t = " + gnum(*s->failed_at) + " s where the reference did not"
                       : "max pose difference " + gnum(s->max_pose_rad, 3) + " rad" +
                             (s->saturated() ? " (beyond its linear regime: amplification at least " + gnum(s->amplification(), 3) + ")"
                                             : ", amplification " + gnum(s->amplification(), 3) + ": round-off grows to " +
                                                   gnum(s->roundoffPoseRad(), 3) + " rad"))
      << (ill.empty() ? ": every threshold is well-conditioned\n"
                      : "; ILL-CONDITIONED at " + joined(ill) + ": errors of that size are the scene's amplification of "
                        "round-off, not a method's, and rank none\n");
  }
  for (const auto& [engine, note] : r.engine_notes) o << "note (" << engine << "): " << note << "\n";
}

}  // namespace

std::string summaryTable(const ComparisonResult& r) {
  std::ostringstream o;
  const bool loops = anyLoops(r.metrics);
  tableHeader(o, r.options.thresholds, loops);
  for (const MethodMetrics& m : r.metrics) tableRow(o, m, loops);
  if (loops) o << "loops open: the largest violation of the loops at the output samples, m or rad, by eigenmass's g(q) for every run\n";
  for (const MethodMetrics& m : r.metrics)
    if (std::isfinite(m.max_joint_separation))
      o << m.name() << ": its joints' two points drifted apart by up to " << gnum(m.max_joint_separation, 3)
        << " m (maximal coordinates: the constraint violation)\n";
  if (r.reference_metrics.tracking) {  // a controlled robot: how each run followed the targets, and the controllers' period
    o << "tracking |q - q*(t)| of the PD targets, max (coordinate, t) and rms: reference " << gnum(r.reference_metrics.tracking->max, 3) << ", "
      << gnum(r.reference_metrics.tracking->rms, 3) << "\n";
    for (const MethodMetrics& m : r.metrics)
      if (m.tracking)
        o << "  " << m.name() << ": " << gnum(m.tracking->max, 3) << " (" << m.tracking->worst << ", " << gnum(m.tracking->max_t, 3) << " s), rms "
          << gnum(m.tracking->rms, 3) << "\n";
  }
  for (const MethodMetrics& m : r.metrics)
    if (const std::optional<ImpactCheck>& c = m.impact_check)
      o << m.name() << ": " << c->count << " impacts (reference " << c->reference_count << "); the first at t "
        << gnum(c->first_time_error, 3) << " s off, rebounding " << gnum(c->first_rebound_error, 3) << " off; over the first " << c->compared
        << ": impact time off by up to " << gnum(c->time_error_max, 3) << " s, rebound speed by " << gnum(c->rebound_error_max, 3)
        << "; beyond a stop by up to " << gnum(c->overshoot_max, 3) << " for " << gnum(c->duration_max, 3) << " s\n";
  referenceLine(o, r);
  if (r.lyapunov && std::isfinite(r.lyapunov->per_s))
    o << "reference motion: finite-time Lyapunov exponent " << gnum(r.lyapunov->per_s, 3) << " /s over the "
      << gnum(r.lyapunov->t_stop) << " s of the run ("
      << (std::isfinite(r.lyapunov->windows_std_per_s)
              ? "its 1-s windows spread +- " + gnum(r.lyapunov->windows_std_per_s, 2) + " /s, standard error " +
                    gnum(r.lyapunov->uncertainty_per_s, 2)
              : std::string("one window"))
      << (r.lyapunov->per_s > 0 ? "; an error grows e-fold every " + gnum(1 / r.lyapunov->per_s, 3) + " s)\n"
                                : std::string("; not positive: nearby motions do not separate over this run, no e-folding time)\n"));
  if (r.lyapunov_long && std::isfinite(r.lyapunov_long->per_s))
    o << "reference motion: long-run Lyapunov exponent " << gnum(r.lyapunov_long->per_s, 3) << " +- "
      << gnum(r.lyapunov_long->uncertainty_per_s, 2) << " /s over " << gnum(r.lyapunov_long->t_stop)
      << " s (standard error of 10-s block means" << (r.lyapunov_long->ok ? "" : "; the twin stopped early") << ")\n";
  if (const auto& st = r.lyapunov_long_starts)
    o << "reference motion: long-run exponent over " << st->starts.size() << " starts (the scene's and "
      << st->starts.size() - 1 << " displaced by " << gnum(st->sigma) << " in q0 and u0): mean " << gnum(st->mean_per_s, 3)
      << " /s, spread (standard deviation) " << gnum(st->spread_per_s, 2) << " /s"
      << (st->completed < static_cast<int>(st->starts.size()) ? ", " + std::to_string(st->completed) + " of them completed" : "")
      << "\n";
  else if (r.lyapunov)
    o << "reference motion: long-run exponent not measured (--lyapunov-long T: over T s, e.g. 300)\n";
  for (const MethodMetrics& m : r.metrics) {
    const MethodInfo& row = info(m.run.method);
    if (row.takes("refine") && row.param("refine", m.run.options) > 0) {
      o << "eigenfactor methods: " << row.param("refine", m.run.options) << " residual correction(s) per evaluation (--refine)\n";
      break;
    }
  }
  for (const MethodMetrics& m : r.metrics)
    if (m.failed())
      o << m.name() << " failed at t = " << gnum(m.failure_time) << " s: " << m.failure << "\n";
  // An adaptive run whose every step the output grid cut: its tolerance set nothing (issue 76).
  if (const std::string note = gridSetStepsNote(r.reference, r.reference.run); !note.empty()) o << "reference: " << note << "\n";
  for (const MethodMetrics& m : r.metrics)
    if (const std::string note = gridSetStepsNote(m, m.run); !note.empty()) o << m.name() << ": " << note << "\n";
  for (const auto& [method, why] : r.options.left_out) o << methodName(method) << ": not run: " << why << "\n";
  o << "outcome: ok; wrong = completed but beyond " << gnum(kWrongRad)
    << " rad of the reference before the reference horizon (only the comparison shows it); failed = stopped.\n";
  o << "pose>x / joint>x: first time (s) the largest body rotation error / joint-angle error against the reference\n"
       "exceeds x rad (- never; * at or beyond the reference horizon, not meaningful).\n"
       "dE/Escl = |E(t) + W_diss(t) - E(0)| / "
    << gnum(r.energy_scale) << " J ("
    << (r.energy_scale_definition == kKineticScale ? "the reference's largest kinetic energy" : r.energy_scale_definition)
    << "; W_diss: work the dampers dissipated).\n";
  return o.str();
}

}  // namespace em
