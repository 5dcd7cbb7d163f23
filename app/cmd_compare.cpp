// `eigenmass compare`: several methods side by side against a reference, a
// JSON report, optionally CSVs and the CI gate.
#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>

#include "app/cli.hpp"
#include "compare/comparison.hpp"
#include "compare/gate.hpp"
#include "compare/report.hpp"

namespace em::cli {

namespace {

// What the command line says of another engine as a compared method.
struct EngineArgs {
  std::string integrator;  ///< --<engine>-integrator ("" for a fixed-step engine: the in-house scheme where it has it)
  double tol = kEngineTol; ///< --<engine>-tol (engines with an adaptive scheme)
};

struct CompareArgs {
  SceneArg scene;
  std::string out, csv_dir, gate;
  std::string reference = methodName(referenceMethod()), reference_integrator;
  std::string integrator = integratorName(defaultIntegrator(Engine::InHouse));
  std::map<Engine, EngineArgs> engines;  ///< every other engine's options, one entry each
  std::vector<std::string> methods = methodNames();
  RunArgs run;
  OutsideArgs outside;  ///< --plugin, --run: methods from outside, compared beside --methods
  CompareOptions opt;
};

// An engine runs at the in-house step, on the in-house scheme where it has it (MuJoCo).
std::string engineOption(Engine e, const char* what) { return std::string("--") + engineName(e) + "-" + what; }

// The adaptive integrators engine `e` runs (what a reference may use).
std::vector<std::string> adaptiveNames(Engine e) {
  std::vector<std::string> names;
  for (const IntegratorInfo& i : integratorTable())
    if (i.runs(e) && !i.fixed_step) names.emplace_back(i.name);
  return names;
}

// The options as given on the command line, resolved against the registry.
CompareOptions resolve(const CompareArgs& a, const CLI::App& cmd, const Model& model, const std::vector<std::string>& outside) {
  CompareOptions o = a.opt;
  o.methods.clear();
  for (const std::string& name : a.methods) o.methods.push_back(parseMethod(name));
  if (!cmd.count("--methods")) o.leaveOutRefused(model);  // named methods are refused instead, in one line
  for (const std::string& name : outside) o.methods.push_back(parseMethod(name));
  const double reference_tol = o.reference.tol;
  o.reference = defaultReferenceSpec(parseMethod(a.reference));
  o.reference.tol = reference_tol;
  if (!cmd.count("--reference")) o.useMechanismReference(model);
  if (!a.reference_integrator.empty()) o.reference.integrator = parseIntegrator(a.reference_integrator);
  // --tol alone selects an adaptive integrator for the in-house methods.
  o.inhouse.integrator = cmd.count("--tol") && !cmd.count("--integrator") ? chosenIntegrator(Engine::InHouse, true)
                                                                          : parseIntegrator(a.integrator);
  for (const auto& [e, ea] : a.engines) {  // a fixed-step engine's --<engine>-integrator runs at --dt (its help; specFor)
    if (!ea.integrator.empty()) o.chooseIntegrator(e, parseIntegrator(ea.integrator));
    o.engines[e].tol = ea.tol;
  }
  refuseUnreadSetting(cmd, o.inhouse.integrator, "--dt", "--tol");
  refuseDuplicates("--thresholds", o.thresholds);
  // The reference honours a tolerance: a fixed-step scheme would run at its
  // own default step and be reported as "tol ...".
  if (info(o.reference.integrator).fixed_step)
    throw std::invalid_argument("--reference-integrator: " + std::string(integratorName(o.reference.integrator)) +
                                " takes a fixed step; the reference needs an adaptive integrator (" +
                                joined(adaptiveNames(info(o.reference.method).engine)) + ")");
  requireCompatible(o.reference.method, o.reference.integrator);
  // Options of an engine none of --methods runs would mean nothing.
  const auto runs = [&](Method m) { return std::find(o.methods.begin(), o.methods.end(), m) != o.methods.end(); };
  for (Engine e : otherEngines())
    for (const char* what : {"integrator", "tol"})
      if (const CLI::Option* opt = cmd.get_option_no_throw(engineOption(e, what)); opt && opt->count() && !runs(info(e).method))
        throw std::invalid_argument(opt->get_name() + ": " + engineName(e) + " is not among --methods");
  refuseUnreadInHouseSettings(o, {cmd.count("--integrator") > 0, cmd.count("--dt") > 0, cmd.count("--tol") > 0});
  const bool inhouse_adaptive = std::any_of(o.methods.begin(), o.methods.end(), [&](Method m) {
    return info(m).engine == Engine::InHouse && !info(o.inhouse.integrator).fixed_step;
  });
  const bool reference_adaptive_inhouse = o.reference.engine() == Engine::InHouse;  // an in-house reference is adaptive
  refuseUnreadRunOptions(cmd, o.methods, inhouse_adaptive || reference_adaptive_inhouse);
  refuseUnreadLoopOptions(cmd, model);
  o.grid = a.run.asked(cmd);
  for (RunSpec* s : o.allSpecs()) a.run.applyTo(*s);
  refuseUnreadFormulationOptions(cmd, o.methods, o.inhouse.integrator, o.inhouse.options.loops.formulation, model);
  o.leaveOutUnrunnable(model, cmd.count("--methods") > 0);
  return o;
}

// The files --csv-dir receives: reference.csv and <method>.csv, each with its .json sidecar.
std::vector<std::string> csvFiles(const std::string& dir, const std::vector<Method>& methods) {
  std::vector<std::string> names = {"reference"}, files;
  for (Method m : methods) names.emplace_back(methodName(m));
  for (const std::string& n : names) {
    files.push_back(dir + "/" + n + ".csv");
    files.push_back(files.back() + ".json");
  }
  return files;
}

void writeCsvs(const ComparisonResult& r, const std::string& dir) {
  writeTrajectory(r.reference, dir + "/reference.csv");
  for (const Trajectory& t : r.runs) writeTrajectory(t, dir + "/" + t.method() + ".csv");
}

// Every run failed, the reference included: nothing was compared.
bool nothingRan(const ComparisonResult& r) {
  if (!r.reference.failed()) return false;
  for (const Trajectory& t : r.runs)
    if (!t.failed()) return false;
  return true;
}

int gateVerdict(const GateResult& g, const std::string& file) {
  if (g.passed) {
    std::printf("gate passed: %zu checks (%s)\n", g.checks.size(), file.c_str());
    return 0;
  }
  std::fputs(brokenChecks(g).c_str(), stdout);
  return 1;
}

int runCompare(const CompareArgs& a, const CLI::App& cmd) {
  // Bad input and unwritable outputs fail here, before any simulation.
  const Scene scene = a.scene.load();
  checkInitialState(scene);
  const Tolerances tol = a.gate.empty() ? Tolerances{} : loadTolerances(a.gate);
  if (!a.gate.empty() && !tol.scenes.count(scene.model.name)) {  // refused before the runs, not after them as a broken gate
    std::vector<std::string> listed;
    for (const auto& [name, bounds] : tol.scenes) listed.push_back(name);
    throw std::invalid_argument("--gate " + a.gate + ": no tolerances for scene '" + scene.model.name + "' (it lists " +
                                (listed.empty() ? std::string("none") : joined(listed)) + ")");
  }
  std::vector<std::string> inputs = {a.scene.path, a.gate};
  for (const std::string& f : a.outside.files()) inputs.push_back(f);
  const std::string out = a.out.empty() ? "out/" + scene.model.name + ".report.json" : a.out;
  prepareOutput("--out", out, inputs);
  const CompareOptions options = resolve(a, cmd, scene.model, a.outside.load(scene));
  if (!a.csv_dir.empty()) {
    const std::vector<std::string> csvs = csvFiles(a.csv_dir, options.methods);
    // The folder itself is an output too: --out X --csv-dir X would run everything, then fail to write the report.
    std::vector<std::pair<std::string, std::string>> outputs = {{"--out", out}, {"--csv-dir", a.csv_dir}};
    for (const std::string& f : csvs) outputs.emplace_back("--csv-dir", f);
    refuseCollisions(outputs);
    prepareFolder("--csv-dir", a.csv_dir);
    refuseInputs("--csv-dir", a.csv_dir, csvs, inputs);
  }
  const ComparisonResult r = runComparison(scene, options, progress);
  nlohmann::json gate = nullptr;
  GateResult g;
  if (!a.gate.empty()) {
    g = evaluateGate(r, tol);
    gate = gateJson(g);
  }
  const Model& m = scene.model;
  if (!a.csv_dir.empty()) writeCsvs(r, a.csv_dir);
  writeJsonAtomic(makeReport(r, gate), out);
  std::printf("%s: %d bodies, %d speeds, t_end %g s, output every %g s\n", m.name.c_str(), m.n(), m.nu, r.t_end,
              r.output_dt);
  std::fputs(summaryTable(r).c_str(), stdout);
  std::printf("report: %s\n", out.c_str());
  if (nothingRan(r)) {
    std::printf("every run failed, the reference included: nothing was compared\n");
    return 1;
  }
  return a.gate.empty() ? 0 : gateVerdict(g, a.gate);
}

// --<engine>-integrator and, for an engine with an adaptive scheme, --<engine>-tol.
void addEngineOptions(CLI::App* cmd, Engine e, EngineArgs& ea) {
  const std::string name = engineName(e), fallback = integratorName(defaultIntegrator(e));
  if (followsInHouse(e)) {
    cmd->add_option(engineOption(e, "integrator"), ea.integrator,
                    helpWithNames("Integrator of the compared " + name + " method, at --dt (default: the in-house one when " +
                                      name + " has it, else " + fallback + ")", integratorNames(e)))
        ->check(integratorValidator(e));
  } else {
    ea.integrator = fallback;
    cmd->add_option(engineOption(e, "integrator"), ea.integrator, helpWithNames("Integrator of the compared " + name + " method", integratorNames(e)))
        ->check(integratorValidator(e))
        ->capture_default_str();
  }
  if (hasAdaptiveScheme(e))  // an engine with a scheme that takes a tolerance
    cmd->add_option(engineOption(e, "tol"), ea.tol, "Accuracy of the compared " + name + " method")
        ->check(positiveFinite())
        ->capture_default_str();
}

void addRunOptions(CLI::App* cmd, CompareArgs& a) {
  CompareOptions& o = a.opt;
  cmd->add_option("--integrator", a.integrator, helpWithNames("Integrator of the in-house methods", integratorNames(Engine::InHouse)))
      ->check(integratorValidator(Engine::InHouse))
      ->capture_default_str();
  auto* dt = cmd->add_option("--dt", o.inhouse.dt, "Fixed step of the in-house methods' fixed-step integrator (s)")
                 ->check(positiveFinite())
                 ->capture_default_str();
  auto* tol = cmd->add_option("--tol", o.inhouse.tol, "Tolerance of adaptive in-house integrators (alone: selects rk8pd; refused with a fixed-step --integrator)")
                  ->check(positiveFinite())
                  ->capture_default_str();
  dt->excludes(tol);
  for (Engine e : otherEngines()) addEngineOptions(cmd, e, a.engines[e]);
  addRunOptions(cmd, a.run, "Common output grid (s)");
}

void addReferenceOptions(CLI::App* cmd, CompareArgs& a) {
  const Method ref = referenceMethod(), inhouse = Method::Classical;
  const auto adaptive = [](Method m) { return std::string(integratorName(adaptiveIntegrator(info(m).engine))); };
  cmd->add_option("--reference", a.reference, std::string("Reference engine: ") + methodName(ref) + " or " +
                                                  methodName(inhouse) + " (in-house)")
      ->check(CLI::IsMember({methodName(ref), methodName(inhouse)}))
      ->capture_default_str();
  cmd->add_option("--reference-integrator", a.reference_integrator,
                  "Integrator of the reference (default " + adaptive(ref) + " for " + methodName(ref) + ", " +
                      adaptive(inhouse) + " for " + methodName(inhouse) + ")")
      ->check(integratorValidator());
  cmd->add_option("--reference-tol", a.opt.reference.tol, "Tolerance (accuracy) of the reference; its horizon run uses 1/100 of it")
      ->check(positiveFinite())
      ->capture_default_str();
}

}  // namespace

void addCompare(CLI::App& app) {
  auto* cmd = app.add_subcommand("compare", "Run several methods side by side against a reference and write a JSON report");
  auto a = std::make_shared<CompareArgs>();
  addSceneArg(cmd, a->scene);
  cmd->add_option("--methods", a->methods, helpWithNames("Methods to compare, comma-separated", methodNames()))
      ->delimiter(',')
      ->check(methodValidator())
      ->capture_default_str();
  addReferenceOptions(cmd, *a);
  addRunOptions(cmd, *a);
  cmd->add_option("--thresholds", a->opt.thresholds, "Pose-error thresholds of the divergence times (rad), comma-separated")
      ->delimiter(',')
      ->check(positiveFinite())
      ->capture_default_str();
  cmd->add_option("--lyapunov-long", a->opt.lyapunov_long_s,
                  "Also measure the reference motion's long-run Lyapunov exponent over this many seconds (e.g. 300), "
                  "apart from the run's finite-time one; costs two classical rk4 runs of that length")
      ->check(positiveFinite());
  cmd->add_option("--lyapunov-starts", a->opt.lyapunov_starts,
                  "With --lyapunov-long: measure it from this many starts, the scene's and neighbours displaced by "
                  "--lyapunov-sigma, and report their mean and spread (1 to 64; each costs what --lyapunov-long does)")
      ->check(CLI::Range(1, kLyapunovStartsMax))
      ->capture_default_str();
  cmd->add_option("--lyapunov-sigma", a->opt.lyapunov_sigma,
                  "With --lyapunov-starts: the neighbours' displacement of every q0 and u0 coordinate (standard deviation)")
      ->check(CLI::Range(1e-300, 0.1))
      ->capture_default_str();
  addOutsideOptions(cmd, a->outside, true);
  cmd->add_option("--out", a->out, "Report file; default out/<scene>.report.json");
  cmd->add_option("--csv-dir", a->csv_dir, "Also write every trajectory (and the reference) as CSV into this folder");
  cmd->add_option("--gate", a->gate, "Tolerance file (data/tolerances.json): exit 1 and list the broken bounds if any");
  cmd->callback([cmd, a] { guarded([&] { return runCompare(*a, *cmd); }); });
}

}  // namespace em::cli
