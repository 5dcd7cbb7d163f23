#include "sweep/plan.hpp"
#include "solver/mechanism/formulation.hpp"

#include "outside/plugin.hpp"
#include "outside/recorded.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>

#include "io/json_input.hpp"
#include "io/run_spec_json.hpp"
#include "io/scene.hpp"
#include "io/scene_json.hpp"
#include "solver/integrate.hpp"
#include "solver/text.hpp"

namespace em {

using json = nlohmann::json;
namespace fs = std::filesystem;

std::string PlanScene::stem() const { return name.empty() ? fs::path(file).stem().string() : name; }

namespace {

// The shortest of gnum's forms that reads back as x: a tuned value names its
// case, its key and its column, so 0.1234574 must not print as 0.123457 (a
// hostile pass found the sweep then reused 0.123457's result for it).
std::string exactNum(double x) {
  for (int digits = 6; digits < 17; ++digits)
    if (const std::string s = gnum(x, digits); std::stod(s) == x) return s;
  return gnum(x, 17);
}

}  // namespace

std::string Tuning::label() const {
  std::string out;
  for (const auto& [key, value] : values) out += (out.empty() ? "" : " ") + key + "=" + exactNum(value);
  return out;
}

std::string Tuning::tag() const {
  std::string out;
  for (const auto& [key, value] : values) out += (out.empty() ? "" : ".") + key + "-" + exactNum(value);
  return out;
}

void Tuning::applyTo(MethodOptions& o) const {
  for (const auto& [key, value] : values)
    if (key == kPenaltyRatioKey) o.loops.penalty_ratio = value;
    else o.params[key] = value;
}

namespace {

struct TableRow {
  PlanTable id;
  const char* name;
};
const TableRow kTables[] = {{PlanTable::WorkPrecision, "work-precision"},
                            {PlanTable::CostVsSize, "cost-vs-size"},
                            {PlanTable::Runs, "runs"},
                            {PlanTable::Trajectories, "trajectories"},
                            {PlanTable::EngineStudy, "engine-study"},
                            {PlanTable::Benchmark, "benchmark"}};

Method methodAt(const json& v, const std::string& path) {
  Method m;
  const std::string name = stringAt(v, path);
  if (!findMethod(name, m)) throw InputError(path, "unknown method '" + printable(name, 40) + "' (" + joined(methodNames()) + ")");
  return m;
}

Integrator integratorAt(const json& v, const std::string& path) {
  Integrator i;
  const std::string name = stringAt(v, path);
  if (!findIntegrator(name, i))
    throw InputError(path, "unknown integrator '" + printable(name, 40) + "' (" + joined(integratorNames()) + ")");
  return i;
}

// "reference" and "reference_check": {"method", "integrator", "tolerance" | "dt"}.
RunSpec runAt(const json& v, const std::string& path) {
  onlyKeys(v, path, {"method", "integrator", "tolerance", "dt"});
  RunSpec s;
  if (!v.contains("method")) throw InputError(jsonPath(path, "method"), "missing");
  s.method = methodAt(v["method"], jsonPath(path, "method"));
  s.integrator = v.contains("integrator") ? integratorAt(v["integrator"], jsonPath(path, "integrator"))
                                          : defaultIntegrator(info(s.method).engine);
  try {
    requireCompatible(s.method, s.integrator);
  } catch (const std::invalid_argument& e) {
    throw InputError(jsonPath(path, "integrator"), e.what());
  }
  const std::string key = settingKeyIn(v, path, s.integrator);
  if (!v.contains(key)) throw InputError(jsonPath(path, key), std::string("missing (") + integratorName(s.integrator) + " takes a " + key + ")");
  s.setSetting(positiveAt(v[key], jsonPath(path, key)));
  return s;
}

double methodParamAt(const MethodParam& m, const json& v, const std::string& path);
constexpr size_t kMaxTuningSets = 100;  // a line's sets: each multiplies its cases
bool readsTuning(Method m, const std::optional<Formulation>& f, const Tuning& t, bool has_loops);

// A line's "tuning": a list of sets, each an object of option keys its
// methods read (a row's params) or "al_penalty_ratio" where the line lists
// the augmented Lagrangian; every set once, none empty.
std::vector<Tuning> tuningsAt(const json& v, const std::string& path, const PlanLine& line) {
  const json sets = nonEmptyArrayAt(v, path);
  if (sets.size() > kMaxTuningSets)
    throw InputError(path, std::to_string(sets.size()) + " sets, more than " + std::to_string(kMaxTuningSets) + ": each is a route of its own");
  std::vector<Tuning> out;
  std::set<std::string> labels;
  const bool al = std::find(line.formulations.begin(), line.formulations.end(), Formulation::AugmentedLagrangian) != line.formulations.end();
  for (size_t i = 0; i < sets.size(); ++i) {
    const std::string at = jsonPath(path, i);
    if (!sets[i].is_object() || sets[i].empty()) throw InputError(at, "expected an object of option values, at least one");
    Tuning t;
    for (const auto& [key, value] : sets[i].items()) {
      const std::string kpath = jsonPath(at, key);
      if (key == kPenaltyRatioKey) {
        if (!al) throw InputError(kpath, "read by the formulation augmented-lagrangian only, which this line does not list");
        const double x = positiveAt(value, kpath);
        if (!(x >= 1 && x <= 1e10)) throw InputError(kpath, "must be in [1, 1e10], got " + gnum(x));
        t.values.emplace_back(key, x);
        continue;
      }
      const MethodParam* param = nullptr;
      for (Method m : line.methods)
        for (const MethodParam& p : info(m).params)
          if (key == p.name) param = &p;
      if (!param) {
        std::vector<std::string> known;
        for (Method m : line.methods)
          for (const MethodParam& p : info(m).params) known.emplace_back(p.name);
        if (al) known.emplace_back(kPenaltyRatioKey);
        throw InputError(kpath, "not an option of this line's methods (" + (known.empty() ? std::string("they have none") : joined(known)) + ")");
      }
      t.values.emplace_back(key, methodParamAt(*param, value, kpath));
    }
    bool read = false;  // by one method whole: a set split over two would run untuned on both
    for (Method m : line.methods) {
      if (al) read = read || readsTuning(m, Formulation::AugmentedLagrangian, t, true);
      read = read || readsTuning(m, std::nullopt, t, true);
    }
    if (!read) throw InputError(at, "no method of this line reads all of its options: one set per method's options");
    if (!labels.insert(t.label()).second) throw InputError(at, "the same set twice");
    out.push_back(t);
  }
  return out;
}

PlanLine lineAt(const json& v, const std::string& path) {
  onlyKeys(v, path, {"methods", "formulations", "integrator", "dt", "tolerance", "tuning"});
  PlanLine line;
  const std::string mpath = jsonPath(path, "methods");
  const json methods = nonEmptyArrayAt(v.contains("methods") ? v["methods"] : json(), mpath);
  for (size_t i = 0; i < methods.size(); ++i) line.methods.push_back(methodAt(methods[i], jsonPath(mpath, i)));
  if (v.contains("formulations")) {
    const std::string fpath = jsonPath(path, "formulations");
    const json list = nonEmptyArrayAt(v["formulations"], fpath);
    for (size_t i = 0; i < list.size(); ++i) {
      Formulation f;
      const std::string name = stringAt(list[i], jsonPath(fpath, i));
      if (!findFormulation(name, f)) {
        std::vector<std::string> known;
        for (const FormulationInfo& row : formulationTable()) known.emplace_back(row.name);
        throw InputError(jsonPath(fpath, i), "unknown formulation '" + printable(name, 40) + "' (" + joined(known) + ")");
      }
      if (std::find(line.formulations.begin(), line.formulations.end(), f) != line.formulations.end())
        throw InputError(jsonPath(fpath, i), "'" + name + "' twice");
      line.formulations.push_back(f);
    }
    for (size_t i = 0; i < line.methods.size(); ++i)
      if (info(line.methods[i]).engine != Engine::InHouse)
        throw InputError(jsonPath(mpath, i), std::string(methodName(line.methods[i])) + " closes loops its own way: a line with "
                                             "\"formulations\" lists in-house methods only");
  }
  if (!v.contains("integrator")) throw InputError(jsonPath(path, "integrator"), "missing");
  line.integrator = integratorAt(v["integrator"], jsonPath(path, "integrator"));
  // A DAE integrator closes the loops itself: each formulation would be a case file of one identical run (issue 73, item 4).
  if (!line.formulations.empty() && info(line.integrator).dae)
    throw InputError(jsonPath(path, "formulations"), std::string("integrator ") + info(line.integrator).name +
                                                         " closes the loops itself (index 2, docs/theory.md §15): a line under it lists no formulations");
  for (size_t i = 0; i < line.methods.size(); ++i) {
    try {
      requireCompatible(line.methods[i], line.integrator);
    } catch (const std::invalid_argument& e) {
      throw InputError(jsonPath(mpath, i), e.what());
    }
  }
  const std::string key = settingKeyIn(v, path, line.integrator);
  const std::string spath = jsonPath(path, key);
  const json settings = nonEmptyArrayAt(v.contains(key) ? v[key] : json(), spath);
  for (size_t i = 0; i < settings.size(); ++i) line.settings.push_back(positiveAt(settings[i], jsonPath(spath, i)));
  if (v.contains("tuning")) line.tunings = tuningsAt(v["tuning"], jsonPath(path, "tuning"), line);
  return line;
}

// A URDF's import options in a scene entry, as the CLI's --balance-inertia, --lock-joint, --floating-base.
UrdfOptions urdfOptionsAt(const json& v, const std::string& at) {
  UrdfOptions u;
  if (v.contains("balance_inertia")) u.balance_inertia = boolAt(v["balance_inertia"], jsonPath(at, "balance_inertia"));
  if (v.contains("floating_base")) u.floating_base = boolAt(v["floating_base"], jsonPath(at, "floating_base"));
  if (v.contains("lock_joint")) {
    const std::string lpath = jsonPath(at, "lock_joint");
    const json joints = nonEmptyArrayAt(v["lock_joint"], lpath);
    for (size_t k = 0; k < joints.size(); ++k) u.lock_joints.push_back(stringAt(joints[k], jsonPath(lpath, k)));
  }
  if (v.contains("damping")) u.damping = boolAt(v["damping"], jsonPath(at, "damping"));
  if (v.contains("ignore_friction")) u.ignore_friction = boolAt(v["ignore_friction"], jsonPath(at, "ignore_friction"));
  if (v.contains("limits_restitution")) {
    const double e = numberAt(v["limits_restitution"], jsonPath(at, "limits_restitution"));
    if (!(e >= 0 && e <= 1)) throw InputError(jsonPath(at, "limits_restitution"), "must be in [0, 1], got " + gnum(e));
    u.limits_restitution = e;
  }
  if (v.contains("control")) u.control_file = stringAt(v["control"], jsonPath(at, "control"));  // resolved against the plan's folder by sceneAt
  return u;
}

// Errors from the import and the engines name the CLI's options; a plan
// spells them as keys: the URDF flags as its scene entry's keys, a method
// option's flag (--mujoco-solref-time) as its own key (mujoco_solref_time).
std::string planSpelling(std::string msg) {
  std::vector<std::pair<std::string, std::string>> names = {{"--balance-inertia", "\"balance_inertia\": true"},
                                                            {"--lock-joint", "\"lock_joint\""},
                                                            {"--floating-base", "\"floating_base\": true"},
                                                            {"--urdf-damping", "\"damping\": true"},
                                                            {"--urdf-ignore-friction", "\"ignore_friction\": true"},
                                                            {"--urdf-limits", "\"limits_restitution\""},
                                                            {"--control", "\"control\""}};
  for (const MethodParam& m : methodParams()) {
    std::string flag = std::string("--") + m.name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    names.emplace_back(flag, m.name);
  }
  std::stable_sort(names.begin(), names.end(), [](const auto& a, const auto& b) { return a.first.size() > b.first.size(); });  // --refine-tol before --refine
  for (const auto& [cli, key] : names)
    for (size_t at = msg.find(cli); at != std::string::npos; at = msg.find(cli, at + key.size())) msg.replace(at, cli.size(), key);
  return msg;
}

// An option read only under another's > 0 (refine_tol under refine): refused at `path` where `under` is not.
void requireReadWhen(const MethodParam& m, double under, const std::string& path) {
  if (!(under > 0)) throw InputError(path, std::string("read only with ") + m.read_when + " > 0, and " + m.read_when + " is " + gnum(under));
}

// Largest displacement sigma of a start (ensemble.perturb.q, start_offset.q):
// one radian (metre). A draw lies within 8.6 sigma (53-bit Box-Muller), so
// every start stays within 8.6 rad (m) of the scene's, inside the bounds its
// own q0 is held to (io/scene_json.cpp). Speeds: kMaxSigmaU rad/s (m/s).
constexpr double kMaxSigmaQ = 1;
constexpr double kMaxSigmaU = 100;

// A displacement's sigma at `at`: 0 when absent, else a finite number from 0 to `max`.
double sigmaAt(const json& v, const char* key, const std::string& at, double max, const char* unit) {
  if (!v.contains(key)) return 0.0;
  const std::string path = jsonPath(at, key);
  const json& x = v[key];
  if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < 0) throw InputError(path, "must be a finite number >= 0");
  if (x.get<double>() > max) {
    const auto [sigma, bound] = gnumApart(x.get<double>(), max);
    throw InputError(path, sigma + " beyond " + bound + " " + unit + ": a displaced start is a nearby state");
  }
  return x.get<double>();
}

// "start_offset": {"q": sigma_q, "u": sigma_u, "seed": S}: the seed is asked for, never chosen.
StartOffset startOffsetAt(const json& v, const std::string& at) {
  onlyKeys(v, at, {"q", "u", "seed"});
  StartOffset o;
  o.q = sigmaAt(v, "q", at, kMaxSigmaQ, "rad (m)");
  o.u = sigmaAt(v, "u", at, kMaxSigmaU, "rad/s (m/s)");
  if (o.q == 0 && o.u == 0) throw InputError(at, "q or u must be > 0: the start would be the scene's own");
  if (!v.contains("seed")) throw InputError(jsonPath(at, "seed"), "missing (the draw's seed: results must say how they were made)");
  o.seed = static_cast<std::uint64_t>(wholeNumberAt(v["seed"], jsonPath(at, "seed"), 0, 2147483647, "the draw's seed"));
  return o;
}

// An entry of `scenes`: "path" or {"file": path, "name", "balance_inertia", "lock_joint", "floating_base", "damping",
// "ignore_friction", "limits_restitution", "control", "start_offset"}.
PlanScene sceneAt(const json& v, const std::string& at, const fs::path& base) {
  PlanScene s;
  std::string file;
  if (v.is_object()) {
    onlyKeys(v, at, {"file", "name", "balance_inertia", "lock_joint", "floating_base", "damping", "ignore_friction", "limits_restitution", "control",
                     "start_offset"});
    file = stringAt(v.value("file", json()), jsonPath(at, "file"));
    if (v.contains("name")) {
      s.name = stringAt(v["name"], jsonPath(at, "name"));
      if (!isSceneName(s.name)) throw InputError(jsonPath(at, "name"), "must be letters, digits, '_' or '-' (1 to 64): it names cases, files and CSV rows");
    }
    s.urdf = urdfOptionsAt(v, at);
    if (!s.urdf.control_file.empty()) {
      const fs::path c = base / s.urdf.control_file;
      if (!fs::is_regular_file(c)) throw InputError(jsonPath(at, "control"), "no such file: " + c.string());
      s.urdf.control_file = c.lexically_normal().string();
    }
    if (v.contains("start_offset")) s.start_offset = startOffsetAt(v["start_offset"], jsonPath(at, "start_offset"));
  } else {
    file = stringAt(v, at);
  }
  const fs::path p = base / file;
  if (!fs::is_regular_file(p)) throw InputError(at, "no such file: " + p.string());
  if (s.urdf.any() && !isUrdfPath(p.string()))
    throw InputError(at, "import options apply to URDF files only (" + p.string() + " is a scene)");
  s.file = p.lexically_normal().string();
  return s;
}

std::vector<PlanScene> scenesAt(const json& v, const std::string& plan_file) {
  const json list = nonEmptyArrayAt(v, "scenes");
  std::vector<PlanScene> out;
  std::set<std::string> stems;
  const fs::path base = fs::path(plan_file).parent_path();
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string at = jsonPath("scenes", i);
    PlanScene s = sceneAt(list[i], at, base);
    // The stem names cases, result files, --list commands and CSV rows: the scene-name rule keeps it safe in all four.
    if (!isSceneName(s.stem()))
      throw InputError(at, "the file's stem must be letters, digits, '_' or '-' (1 to 64): it names cases, files and CSV rows");
    if (!stems.insert(s.stem()).second) throw InputError(at, "a second scene named '" + s.stem() + "'");
    try {  // an invalid scene is refused here, once, not once per case at run time
      const Scene scene = loadScene(s.file, s.urdf);
      s.has_loops = !scene.model.loops.empty();
      s.benchmark = scene.benchmark;
      for (const MethodInfo& row : methodTable())
        if (!row.retired)
          if (std::string why = methodRefusal(row.id, scene.model); !why.empty()) s.refusals[row.name] = std::move(why);
    } catch (const std::exception& e) {
      throw InputError(at, planSpelling(e.what()));
    }
    if (s.start_offset && s.has_loops)
      throw InputError(jsonPath(at, "start_offset"), "the scene has loops: a displaced start would leave them open");
    out.push_back(s);
  }
  return out;
}

// "plugins": {"NAME": "path/libx.so", ...}: methods from outside (outside/plugin.hpp),
// paths against the plan's folder, each probed at every scene's initial state.
void pluginsAt(const json& v, const std::string& plan_file, const std::vector<PlanScene>& scenes) {
  if (!v.is_object()) throw InputError("plugins", "expected an object {\"NAME\": \"path/libx.so\"}");
  const fs::path base = fs::path(plan_file).parent_path();
  for (const auto& [name, path] : v.items()) {
    const std::string at = jsonPath("plugins", name);
    const fs::path file = base / stringAt(path, at);
    try {
      const Method m = addPlugin(name, file.string());
      for (const PlanScene& s : scenes) probePlugin(m, loadScene(s.file, s.urdf).model);
    } catch (const std::exception& e) {
      throw InputError(at, e.what());
    }
  }
}

// "runs": {"NAME": "file.csv", ...}: runs made elsewhere (outside/recorded.hpp) of the
// plan's one scene, paths against the plan's folder, each read and checked now.
std::vector<Method> runsAt(const json& v, const Plan& p) {
  if (!v.is_object()) throw InputError("runs", "expected an object {\"NAME\": \"file.csv\"}");
  if (p.scenes.size() != 1)
    throw InputError("runs", "a recorded run is of one scene; this plan has " + std::to_string(p.scenes.size()));
  if (p.ensemble) throw InputError("runs", "a recorded run is one motion; an ensemble's members would each need their own");
  const Scene scene = loadScene(p.scenes[0].file, p.scenes[0].urdf);
  std::vector<Method> out;
  for (const auto& [name, path] : v.items()) {
    const std::string at = jsonPath("runs", name);
    const fs::path file = fs::path(p.file).parent_path() / stringAt(path, at);
    try {
      out.push_back(addRecordedRun(name, file.string(), scene.model));
    } catch (const std::exception& e) {
      throw InputError(at, e.what());
    }
  }
  return out;
}

std::vector<PlanTable> tablesAt(const json& v) {
  std::vector<PlanTable> out;
  if (!v.is_array()) throw InputError("tables", "expected a list");
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string name = stringAt(v[i], jsonPath("tables", i));
    const auto* row = std::find_if(std::begin(kTables), std::end(kTables), [&](const TableRow& r) { return name == r.name; });
    if (row == std::end(kTables)) {
      std::vector<std::string> known;
      for (const TableRow& r : kTables) known.emplace_back(r.name);
      throw InputError(jsonPath("tables", i), "unknown table '" + printable(name, 40) + "' (" + joined(known) + ")");
    }
    out.push_back(row->id);
  }
  return out;
}

// A method option's value at `path`, within its row's bounds.
double methodParamAt(const MethodParam& m, const json& v, const std::string& path) {
  if (m.whole) return wholeNumberAt(v, path, int(m.min), int(m.max), "a method option");
  const double x = positiveAt(v, path);
  if (!(x > m.min && x <= m.max)) throw InputError(path, "must be in (" + gnum(m.min) + ", " + gnum(m.max) + "], got " + gnum(x));
  return x;
}

// The methods' own options (the registry rows' params) at their keys.
void readMethodParams(const json& doc, MethodOptions& options) {
  for (const MethodParam& m : methodParams())
    if (doc.contains(m.name)) options.params[m.name] = methodParamAt(m, doc[m.name], m.name);
  for (const MethodParam& m : methodParams())  // an option read only under another's > 0 (refine_tol under refine)
    if (m.read_when && doc.contains(m.name)) {
      const auto it = options.params.find(m.read_when);
      requireReadWhen(m, it != options.params.end() ? it->second : methodParam(m.read_when).fallback, m.name);
    }
}

// "ensemble.claim": {"t_s": T, "label": L}, T within the plan's t_end.
EnsembleClaim claimAt(const json& v, double t_end) {
  onlyKeys(v, "ensemble.claim", {"t_s", "label"});
  EnsembleClaim c;
  c.t_s = positiveAt(v.value("t_s", json()), "ensemble.claim.t_s");
  if (c.t_s > t_end) throw InputError("ensemble.claim.t_s", gnum(c.t_s) + " beyond the plan's t_end " + gnum(t_end));
  c.label = stringAt(v.value("label", json()), "ensemble.claim.label");
  if (c.label.empty() || c.label.size() > 80 ||
      std::any_of(c.label.begin(), c.label.end(), [](char ch) { return static_cast<unsigned char>(ch) < 0x20; }))
    throw InputError("ensemble.claim.label", "1 to 80 characters without a control character: figures print it");
  return c;
}

// "ensemble": {"count": N, "seed": S, "perturb": {"q": sigma_q, "u": sigma_u}, "claim": {...}}.
Ensemble ensembleAt(const json& v, double t_end) {
  onlyKeys(v, "ensemble", {"count", "seed", "perturb", "claim"});
  Ensemble e;
  if (!v.contains("count")) throw InputError("ensemble.count", "missing");
  e.count = wholeNumberAt(v["count"], "ensemble.count", 1, 100000, "members per scene");
  if (v.contains("seed")) e.seed = static_cast<std::uint64_t>(wholeNumberAt(v["seed"], "ensemble.seed", 0, 2147483647, "the draws' seed"));
  if (!v.contains("perturb")) throw InputError("ensemble.perturb", "missing");
  const json& p = v["perturb"];
  onlyKeys(p, "ensemble.perturb", {"q", "u"});
  e.sigma_q = sigmaAt(p, "q", "ensemble.perturb", kMaxSigmaQ, "rad (m)");
  e.sigma_u = sigmaAt(p, "u", "ensemble.perturb", HUGE_VAL, "rad/s (m/s)");  // bounded per scene below (its speeds' range)
  if (e.count > 1 && e.sigma_q == 0 && e.sigma_u == 0)
    throw InputError("ensemble.perturb", "q or u must be > 0: every member would be the scene itself");
  if (v.contains("claim")) e.claim = claimAt(v["claim"], t_end);
  return e;
}

// The benchmark table measures every scene's "benchmark" at its output steps:
// each scene must have one, and the plan's output grid must hold its steps.
void checkBenchmarkGrid(const Plan& p) {
  for (const PlanScene& s : p.scenes) {
    if (!s.benchmark)
      throw InputError("tables", "benchmark: scene " + s.stem() + " has no \"benchmark\" key (its error measure and levels, docs/scene-format.md)");
    const double ratio = s.benchmark->outputStep() / p.output_dt;
    if (!(std::abs(ratio - std::round(ratio)) <= 1e-9 * ratio) || std::round(ratio) < 1)
      throw InputError("output_dt", gnum(p.output_dt) + " s does not divide scene " + s.stem() + "'s benchmark output step " +
                                        gnum(s.benchmark->outputStep()) + " s (t_end / outputs)");
  }
}

void readPlanKeys(const json& doc, Plan& p) {
  std::vector<std::string> keys = {"format", "name", "description", "scenes", "t_end", "output_dt", "repeats",
                                   "reference", "reference_check", "lines", "tables", "max_steps", "max_samples", "ensemble", "plugins", "runs"};
  for (const MethodParam& m : methodParams()) keys.emplace_back(m.name);
  if (doc.is_object() && doc.value("format", json()) == "eigenmass-scene/1")
    throw InputError("format", "a scene, not a plan (eigenmass-plan/1, docs/sweep.md): compare, simulate or extreme take a scene");
  onlyKeys(doc, "", keys);
  if (stringAt(doc.value("format", json()), "format") != "eigenmass-plan/1")
    throw InputError("format", "expected \"eigenmass-plan/1\"");
  p.name = stringAt(doc.value("name", json()), "name");
  if (!isSceneName(p.name))
    throw InputError("name", "must be letters, digits, '_' or '-' (1 to 64): it names the results folder, files and commands");
  if (doc.contains("description")) p.description = stringAt(doc["description"], "description");
  if (std::any_of(p.description.begin(), p.description.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20; }))
    throw InputError("description", "a control character (newline, escape): it is printed in the tables as one line");
  p.scenes = scenesAt(doc.value("scenes", json()), p.file);
  if (doc.contains("plugins")) pluginsAt(doc["plugins"], p.file, p.scenes);  // before the lines that name them
  p.t_end = positiveAt(doc.value("t_end", json()), "t_end");
  if (doc.contains("output_dt")) p.output_dt = positiveAt(doc["output_dt"], "output_dt");
  if (doc.contains("ensemble")) {
    p.ensemble = ensembleAt(doc["ensemble"], p.t_end);
    for (const PlanScene& s : p.scenes)
      if (const std::string why = ensembleBeyondBounds(loadScene(s.file, s.urdf).model, *p.ensemble); !why.empty())
        throw InputError("ensemble.perturb", "scene " + s.stem() + ": a member may reach " + why + " (members lie within " +
                                                 gnum(kDrawBound) + " sigma of the scene's state)");
  }
  // An ensemble reads divergence, not timing: it may run each case once.
  if (doc.contains("repeats"))
    p.repeats = p.ensemble ? wholeNumberAt(doc["repeats"], "repeats", 1, 100, "an ensemble may time each case once")
                           : wholeNumberAt(doc["repeats"], "repeats", 3, 100, "timings are medians");
  if (doc.contains("reference")) p.reference = runAt(doc["reference"], "reference");
  if (doc.contains("reference_check")) {
    if (!p.reference) throw InputError("reference_check", "needs a reference to check");
    p.reference_check = runAt(doc["reference_check"], "reference_check");
  }
  const json lines = nonEmptyArrayAt(doc.value("lines", json()), "lines");
  for (size_t i = 0; i < lines.size(); ++i) p.lines.push_back(lineAt(lines[i], jsonPath("lines", i)));
  if (doc.contains("runs")) p.runs = runsAt(doc["runs"], p);  // after the lines: no line may name the recorded scheme
  if (doc.contains("tables")) p.tables = tablesAt(doc["tables"]);
  for (PlanTable t : {PlanTable::WorkPrecision, PlanTable::EngineStudy, PlanTable::Benchmark})
    if (p.hasTable(t) && !p.reference) throw InputError("tables", std::string(planTableName(t)) + " needs a reference");
  if (p.hasTable(PlanTable::Benchmark)) checkBenchmarkGrid(p);
  if (doc.contains("max_steps")) p.options.max_steps = positiveAt(doc["max_steps"], "max_steps");
  if (doc.contains("max_samples")) p.options.max_samples = positiveAt(doc["max_samples"], "max_samples");
  readMethodParams(doc, p.options);
  for (size_t i = 0; i < p.lines.size(); ++i) {
    const std::string tpath = jsonPath(jsonPath("lines", i), "tuning");
    // An ensemble's distribution tables name a route by method and scheme alone: tuned routes would be pooled there.
    if (p.ensemble && !p.lines[i].tunings.empty())
      throw InputError(tpath, "not with an ensemble: its distribution tables would pool the tuned routes with the untuned");
    for (size_t k = 0; k < p.lines[i].tunings.size(); ++k) {
      const Tuning& t = p.lines[i].tunings[k];
      for (const auto& [key, value] : t.values) {
        const std::string at = jsonPath(tpath, k) + "." + key;
        if (doc.contains(key)) throw InputError(at, "also set at the plan's top level: set it in one place");
        if (key == kPenaltyRatioKey) continue;
        const MethodParam m = methodParam(key);  // an option read only under another's > 0 (refine_tol under refine)
        if (!m.read_when) continue;
        const auto in_set = std::find_if(t.values.begin(), t.values.end(), [&](const auto& kv) { return kv.first == m.read_when; });
        const auto in_plan = p.options.params.find(m.read_when);
        requireReadWhen(m, in_set != t.values.end() ? in_set->second
                           : in_plan != p.options.params.end() ? in_plan->second : methodParam(m.read_when).fallback, at);
      }
    }
  }
}

// Every run of the plan on its grid: planCases checks each case's settings
// as it makes it (checkedCase), before anything runs; here, that no case is
// listed twice, and that every in-house case can run its scene (issue 73, item
// 9: the augmented Lagrangian under rk4, the projection under cvode, a plugin
// under ida loaded and listed, then failed case by case with exit 1). An
// engine's refusals are the scene's own (PlanScene::refusals: left out, said).
void checkPlanRuns(const Plan& p) {
  std::set<std::string> names;
  std::vector<std::optional<Model>> models(p.scenes.size());
  for (const SweepCase& c : planCases(p)) {
    if (!names.insert(c.name).second) throw InputError("lines", "case " + c.name + " appears twice");
    const PlanScene& scene = p.scenes[c.scene];
    if (scene.refusals.count(methodName(c.spec->method)) || !info(c.spec->integrator).stepped()) continue;  // left out; a recorded run
    if (!models[c.scene]) models[c.scene].emplace(loadScene(scene.file, scene.urdf).model);
    if (info(c.spec->method).engine != Engine::InHouse) {  // an engine's options as the case would run them (MuJoCo's solref vs dt)
      try {
        requireSettingsTaken(c.spec, *models[c.scene]);
      } catch (const std::invalid_argument& e) {
        throw InputError("lines", c.name + ": " + planSpelling(e.what()));
      }
      continue;
    }
    try {
      refuseUnrunnable(*models[c.scene], c.spec);
    } catch (const std::invalid_argument& e) {
      throw InputError(c.role == CaseRole::Run ? "lines" : c.role == CaseRole::Reference ? "reference" : "reference_check",
                       c.name + ": " + e.what());
    }
  }
}

}  // namespace

// Every case role and its name in the files, in CaseRole's order.
struct RoleRow {
  CaseRole id;
  const char* name;
};
constexpr RoleRow kRoles[] = {{CaseRole::Reference, "reference"}, {CaseRole::Check, "check"}, {CaseRole::Run, "run"}};
static_assert(std::size(kRoles) == static_cast<size_t>(CaseRole::Run) + 1, "a row per case role");

const char* caseRoleName(CaseRole r) {
  for (const RoleRow& row : kRoles)
    if (row.id == r) return row.name;
  return "?";
}

bool findCaseRole(const std::string& name, CaseRole& out) {
  for (const RoleRow& row : kRoles)
    if (name == row.name) {
      out = row.id;
      return true;
    }
  return false;
}

const char* planTableName(PlanTable t) {
  for (const TableRow& r : kTables)
    if (r.id == t) return r.name;
  return "?";
}

bool Plan::hasTable(PlanTable t) const { return std::find(tables.begin(), tables.end(), t) != tables.end(); }

Plan parsePlan(const std::string& text, const std::string& path, const std::string& named) {
  Plan p;
  p.file = path;
  try {
    readPlanKeys(parseJsonStrict(text), p);
    checkPlanRuns(p);
  } catch (const InputError& e) {
    throw std::runtime_error(named + ": " + e.what());
  }
  return p;
}

Plan loadPlan(const std::string& path) { return parsePlan(readFile(path, "plan"), path, path); }

namespace {

// "m007": a member's part of its case names, wide enough for the plan's count.
std::string memberTag(const Plan& p, int member) {
  const int width = std::max(3, static_cast<int>(std::to_string(p.ensemble->count - 1).size()));
  std::string digits = std::to_string(member);
  return "m" + std::string(width - std::min<int>(width, digits.size()), '0') + digits;
}

// A case's spec, checked: a setting that cannot run is refused with the key that gave it.
CheckedRunSpec checkedCase(const RunSpec& spec, CaseRole role, const std::string& name) {
  const char* key = role == CaseRole::Run ? "lines" : role == CaseRole::Reference ? "reference" : "reference_check";
  try {
    return checked(spec, "the plan keys max_steps and max_samples raise the budgets");
  } catch (const SettingError& e) {  // the grid is the plan's own keys, not the reference's or a line's
    if (e.field == "t_end" || e.field == "output_dt") throw InputError(e.field, e.detail);
    throw InputError(key, name + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    throw InputError(key, name + ": " + e.what());
  }
}

SweepCase makeCase(const Plan& p, size_t scene, int member, CaseRole role, RunSpec spec,
                   std::optional<Formulation> formulation = std::nullopt, const Tuning& tuning = {}) {
  const std::string scene_name = p.scenes[scene].stem();
  const std::string stem = p.ensemble ? scene_name + "." + memberTag(p, member) : scene_name;
  spec.t_end = p.t_end;
  spec.output_dt = p.output_dt;
  spec.diagnostics = false;  // errors and cost only
  spec.options = p.options;
  std::string name;
  if (formulation) spec.options.loops.formulation = *formulation;
  const std::string route = methodName(spec.method) + (formulation ? std::string(".") + formulationName(*formulation) : "");
  if (role == CaseRole::Reference) name = stem + ".reference";
  else if (role == CaseRole::Check) name = stem + ".check";
  else name = stem + "." + route + "." + integratorName(spec.integrator) + "." + gnum(spec.setting());
  tuning.applyTo(spec.options);
  if (!tuning.values.empty()) name += "." + tuning.tag();
  return SweepCase{role, scene, scene_name, member, checkedCase(spec, role, name), name, formulation.has_value(), tuning.label()};
}

// Whether method m (under formulation f) reads every value of the set: a
// line of two engines may tune each apart; a set it does not read is not its run.
bool readsTuning(Method m, const std::optional<Formulation>& f, const Tuning& t, bool has_loops) {
  for (const auto& [key, value] : t.values) {
    if (key == kPenaltyRatioKey) {
      if (!f || *f != Formulation::AugmentedLagrangian) return false;
      continue;
    }
    const std::vector<MethodParam>& params = info(m).params;
    const auto p = std::find_if(params.begin(), params.end(), [&](const MethodParam& q) { return key == q.name; });
    if (p == params.end() || (p->loops_only && !has_loops)) return false;  // (a stops' option is read where the scene has stops)
  }
  return true;
}

// The sets of `line` that method m under f runs on a scene: those it reads
// whole there. A method the sets are not for (classical beside MuJoCo's
// solref) runs once at the plan's options; one they are for runs none where
// the scene reads none of them (a closure's options on a tree: the untuned
// line's runs are those runs, and leftOutLines says so).
// Whether the set is for method m on some scene: read whole under no formulation or one of the line's, with loops.
bool setFor(const PlanLine& line, Method m, const Tuning& t) {
  if (readsTuning(m, std::nullopt, t, true)) return true;
  return std::any_of(line.formulations.begin(), line.formulations.end(), [&](Formulation f) { return readsTuning(m, f, t, true); });
}

std::vector<Tuning> tuningsOf(const PlanLine& line, Method m, const std::optional<Formulation>& f, bool has_loops) {
  std::vector<Tuning> out;
  bool for_m = false;
  for (const Tuning& t : line.tunings) {
    // Per formulation: the augmented Lagrangian's penalty is not for the
    // projection beside it, which then runs untuned (and is refused where it
    // cannot run, as without the set: a hostile pass found it silently dropped).
    for_m = for_m || (f ? readsTuning(m, f, t, true) : setFor(line, m, t));
    if (readsTuning(m, f, t, has_loops)) out.push_back(t);
  }
  if (!for_m) out.emplace_back();
  return out;
}

}  // namespace

SweepCase referenceCaseOf(const Plan& p, const SweepCase& c) {
  return makeCase(p, c.scene, c.member, CaseRole::Reference, *p.reference);
}

std::vector<SweepCase> planCases(const Plan& p) {
  std::vector<SweepCase> cases;
  const int members = p.ensemble ? p.ensemble->count : 1;
  for (size_t s = 0; s < p.scenes.size(); ++s)
    for (int k = 0; k < members; ++k) {
      if (p.reference) cases.push_back(makeCase(p, s, k, CaseRole::Reference, *p.reference));
      if (p.reference_check) cases.push_back(makeCase(p, s, k, CaseRole::Check, *p.reference_check));
    }
  for (size_t s = 0; s < p.scenes.size(); ++s)
    for (int k = 0; k < members; ++k)
      for (const PlanLine& line : p.lines) {
        // A line's formulations name its cases on a scene with loops; on a tree there is none to choose.
        std::vector<std::optional<Formulation>> forms = {std::nullopt};
        if (p.scenes[s].has_loops && !line.formulations.empty()) forms.assign(line.formulations.begin(), line.formulations.end());
        for (Method m : line.methods)
          for (const std::optional<Formulation>& f : forms)
            if (!p.scenes[s].refusals.count(methodName(m)))  // left out, and said (leftOutLines)
              for (double setting : line.settings)
                for (const Tuning& t : tuningsOf(line, m, f, p.scenes[s].has_loops)) {
                  RunSpec spec;
                  spec.method = m;
                  spec.integrator = line.integrator;
                  spec.setSetting(setting);
                  cases.push_back(makeCase(p, s, k, CaseRole::Run, spec, f, t));
                }
      }
  for (Method m : p.runs) {  // a recorded run's case, named with the plan's output step (its samples are put on that grid)
    RunSpec spec;
    spec.method = m;
    spec.integrator = recordedScheme();
    spec.dt = p.output_dt;
    cases.push_back(makeCase(p, 0, 0, CaseRole::Run, spec));
  }
  return cases;
}

std::string leftOutLines(const Plan& p) {
  std::string out;
  const int members = p.ensemble ? p.ensemble->count : 1;
  for (const PlanScene& sc : p.scenes) {
    std::vector<std::pair<std::string, std::vector<std::string>>> by_reason;  // (why, methods), in the lines' order
    long cases = 0;
    for (const PlanLine& line : p.lines) {
      std::vector<std::optional<Formulation>> forms = {std::nullopt};
      if (sc.has_loops && !line.formulations.empty()) forms.assign(line.formulations.begin(), line.formulations.end());
      for (Method m : line.methods) {
        const auto it = sc.refusals.find(methodName(m));
        if (it == sc.refusals.end()) continue;
        for (const std::optional<Formulation>& f : forms)
          cases += static_cast<long>(tuningsOf(line, m, f, sc.has_loops).size() * line.settings.size()) * members;
        auto same = std::find_if(by_reason.begin(), by_reason.end(), [&](const auto& r) { return r.first == it->second; });
        if (same == by_reason.end()) by_reason.push_back({it->second, {}}), same = by_reason.end() - 1;
        if (std::find(same->second.begin(), same->second.end(), it->first) == same->second.end()) same->second.push_back(it->first);
      }
    }
    long closure_sets = 0;  // on a tree: runs of sets that tune closures alone (tuningsOf)
    for (const PlanLine& line : p.lines)
      for (Method m : line.methods)
        for (const Tuning& t : line.tunings)
          if (!sc.has_loops && !sc.refusals.count(methodName(m)) && setFor(line, m, t) && !readsTuning(m, std::nullopt, t, false))
            closure_sets += static_cast<long>(line.settings.size()) * members;
    if (by_reason.empty() && closure_sets == 0) continue;
    if (!by_reason.empty()) {
      out += "**Not run on " + sc.stem() + "** (" + std::to_string(cases) + " cases of the plan's lines left out):";
      for (const auto& [why, methods] : by_reason) out += " " + joined(methods) + ": " + why + ".";
      out += "\n\n";
    }
    if (closure_sets > 0)
      out += "**Not run on " + sc.stem() + "**: " + std::to_string(closure_sets) + (closure_sets == 1 ? " case" : " cases") + " of tuning sets that set closures' "
             "options or a formulation's (a tree has no closure: they would be the untuned runs again).\n\n";
  }
  return out;
}

}  // namespace em
