#include "app/cli.hpp"

#include "outside/plugin.hpp"
#include "outside/recorded.hpp"
#include "outside/isolate.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "compare/progress.hpp"
#include "compare/provenance.hpp"
#include "compare/report.hpp"
#include "io/run_spec_json.hpp"
#include "solver/mechanism/formulation.hpp"
#include "io/atomic_file.hpp"
#include "io/csv.hpp"
#include "solver/text.hpp"

namespace em::cli {

namespace {
int g_exit = 0;
}  // namespace

int exitCode() { return g_exit; }

std::string oneLine(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else if (c < 0x20 || c == 0x7f) {  // an escape sequence would drive the terminal
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    } else out += ch;  // UTF-8 (u′, ±) as it is
  }
  return out;
}

void guarded(const std::function<int()>& body) {
  try {
    g_exit = body();
  } catch (const std::exception& e) {
    // One line, whatever the message quotes: a path or a value read from outside may hold a line break.
    std::fprintf(stderr, "eigenmass: error: %s\n", oneLine(e.what()).c_str());
    g_exit = 2;
  }
}

namespace {

namespace fs = std::filesystem;

// A file can be created in `dir` (checked by creating and removing one).
bool writableFolder(const fs::path& dir) {
  std::string probe = (dir.empty() ? fs::path(".") : dir) / ".eigenmass-probe-XXXXXX";
  const int fd = ::mkstemp(probe.data());
  if (fd < 0) return false;
  ::close(fd);
  ::unlink(probe.c_str());
  return true;
}

}  // namespace

void prepareFolder(const std::string& option, const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !writableFolder(dir)) throw std::runtime_error(option + " " + dir + ": cannot write into this folder");
}

void refuseInputs(const std::string& option, const std::string& given, const std::vector<std::string>& written,
                  const std::vector<std::string>& inputs) {
  std::error_code ec;
  for (const std::string& w : written)
    for (const std::string& in : inputs)
      if (!in.empty() && fs::equivalent(w, in, ec))
        throw std::runtime_error(option + " " + given + (w == given ? ": is" : ": would write " + w + ", which is") +
                                 " an input file; refusing to overwrite it");
}

void refuseCollisions(const std::vector<std::pair<std::string, std::string>>& outputs) {
  std::vector<fs::path> canonical;
  for (const auto& [who, path] : outputs) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
    if (ec) p = fs::absolute(path).lexically_normal();
    for (size_t i = 0; i < canonical.size(); ++i)
      if (canonical[i] == p)
        throw std::runtime_error(outputs[i].first + " and " + who + " would both write " + path +
                                 ": one output would replace the other");
    canonical.push_back(p);
  }
}

void prepareOutput(const std::string& option, const std::string& path, const std::vector<std::string>& inputs,
                   const std::vector<std::string>& derived) {
  std::error_code ec;
  refuseInputs(option, path, {path}, inputs);
  refuseInputs(option, path, derived, inputs);
  if (fs::is_directory(path, ec)) throw std::runtime_error(option + " " + path + ": is a folder, not a file");
  const fs::path dir = fs::path(path).parent_path();
  if (!dir.empty()) prepareFolder(option, dir.string());
  else if (!writableFolder(dir)) throw std::runtime_error(option + " " + path + ": cannot write into the current folder");
}

void writeTrajectory(const Trajectory& tr, const std::string& path, const SceneSource* source) {
  writeCsv(tr, path);
  const RunSpec& r = tr.run;
  nlohmann::json meta = {{"format", "eigenmass-trajectory-meta/1"},
                         {"csv", fs::path(path).filename().string()},
                         {"scene", tr.scene},
                         {"method", tr.method()},
                         {"integrator", tr.integrator()},
                         {settingKindName(r.settingKind()), r.setting()},
                         {"t_end", r.t_end},
                         {"output_dt", r.output_dt},
                         {"status", outcomeName(tr.status())},
                         {"failure", tr.failed() ? failureJson(tr.failure_time, tr.failure_kind, tr.failure, tr.failure_cond_A)
                                                 : nlohmann::json(nullptr)},
                         {"steps", tr.steps},
                         {"rhs_evals", tr.rhs_evals},
                         {"run_time_s", tr.run_time_s},
                         {"provenance", provenance()}};
  if (tr.has_loops) meta["loops"] = loopsJson(tr, tr.run);
  if (!tr.stops.empty() || tr.impact_count > 0) {  // joint limits: the stops and every impact (the first kImpactsKept), docs/report-format.md
    nlohmann::json list = nlohmann::json::array();
    for (const Impact& i : tr.impacts)
      list.push_back({{"t", i.t}, {"coordinate", i.coordinate}, {"u_before", i.u_before}, {"u_after", i.u_after},
                      {"energy_lost_J", std::isfinite(i.energy_lost) ? nlohmann::json(i.energy_lost) : nlohmann::json()}, {"rests", i.rests},
                      {"overshoot", i.overshoot}, {"duration_s", i.duration}});
    nlohmann::json stops = nlohmann::json::array();
    for (const LimitedCoordinate& c : tr.stops)
      stops.push_back({{"coordinate", c.name}, {"lower", c.lower}, {"upper", c.upper}, {"restitution", c.restitution}});
    meta["limits"] = stops;
    meta["impacts"] = {{"count", tr.impact_count}, {"kept", tr.impacts.size()}, {"each", list},
                       {"how", tr.run.engine() == Engine::InHouse
                                   ? "exact events: located to 1e-12 s, Newton's law through A (docs/theory.md §17)"
                                   : "the engine's own stop, watched after every step: t where the coordinate crossed the stop, "
                                     "u_before at the last step inside, u_after at the first step back inside, overshoot how far "
                                     "beyond it went (rad or m), duration_s how long; energy_lost_J not measured"}};
  }
  const MethodInfo& row = info(r.method);
  for (const MethodParam& p : row.params)  // the method's own options as run (an engine's: its joints' or closures' stabilization)
    if ((!p.loops_only || tr.has_loops) && (!p.limits_only || !tr.stops.empty())) meta["options"][p.name] = row.param(p.name, r.options);
  if (std::isfinite(tr.max_joint_separation)) meta["max_joint_separation_m"] = tr.max_joint_separation;
  if (source) meta["scene_source"] = sceneSourceJson(*source);  // the file's digest, import notes, an assembly
  if (!regularOutput(path)) {  // a device, a FIFO (/dev/stdout, /dev/null): no sidecar beside it, the metadata on stderr
    std::fprintf(stderr, "eigenmass: %s is not a regular file, so no %s.json beside it; its metadata: %s\n", path.c_str(),
                 path.c_str(), meta.dump().c_str());
    return;
  }
  writeAtomic(path + ".json", "trajectory metadata", [&](std::ostream& out) { out << meta.dump(2) << "\n"; });
}

bool regularOutput(const std::string& path) { return !writesThrough(path); }

void refuseUnreadSetting(const CLI::App& cmd, Integrator integrator, const std::string& dt_option, const std::string& tol_option) {
  const bool fixed = info(integrator).fixed_step;
  if (fixed && cmd.count(tol_option))
    throw std::invalid_argument(tol_option + ": " + integratorName(integrator) + " takes a fixed step (" + dt_option + ")");
  if (!fixed && cmd.count(dt_option))
    throw std::invalid_argument(dt_option + ": " + integratorName(integrator) + " is adaptive (" + tol_option + ")");
}

namespace {
// A finite number for which ok(x) holds, else "expected a number, got ..." or "must be <what>, got ...".
template <class Ok>
CLI::Validator finiteNumber(Ok ok, const std::string& what, const std::string& description) {
  return CLI::Validator(
      [ok, what](std::string& text) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0') return "expected a number, got '" + text + "'";
        if (!std::isfinite(x) || !ok(x)) return "must be " + what + ", got " + text;
        return "";
      },
      description);
}
}  // namespace

CLI::Validator positiveFinite() { return finiteNumber([](double x) { return x > 0; }, "a finite number > 0", "> 0"); }

// CLI::Range lets NaN through (every comparison with it is false).
CLI::Validator finiteRange(double lo, double hi) {
  const std::string range = "[" + gnum(lo) + ", " + gnum(hi) + "]";
  return finiteNumber([lo, hi](double x) { return x >= lo && x <= hi; }, "a finite number in " + range, "in " + range);
}

void refuseEmptyPaths(CLI::App& app) {
  static const char* const kPathOptions[] = {"--out", "--csv-dir", "--out-dir", "--doc", "--results",
                                             "--merge", "--gate", "--expect", "--run", "--plugin"};
  const CLI::Validator nonEmpty(
      [](std::string& v) { return v.empty() ? std::string("an empty path (leave the option out for its default)") : std::string(); },
      "");
  for (CLI::App* sub : app.get_subcommands({}))
    for (const char* name : kPathOptions)
      if (CLI::Option* o = sub->get_option_no_throw(name)) o->check(nonEmpty);
}

Grid RunArgs::asked(const CLI::App& cmd) const {
  Grid g;
  if (cmd.count("--t-end")) g.t_end = t_end;
  if (cmd.count("--output-dt")) g.output_dt = output_dt;
  return g;
}

void RunArgs::applyTo(MethodOptions& options) const {
  if (allow_long_run) options.max_steps = options.max_samples = HUGE_VAL;
  options.params = params;
  options.retry_failed_steps = !no_step_retry;
  options.loops = loops;
  findFormulation(formulation, options.loops.formulation);  // the option's validator admitted only table names
}

namespace {

// "--block-gap" for the option "block_gap".
std::string optionName(const MethodParam& p) {
  std::string flag = std::string("--") + p.name;
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

// A method option's CLI validator: a whole number in [min, max], or a finite number in (min, max].
CLI::Validator paramValidator(const MethodParam& p) {
  const double lo = p.min, hi = p.max;
  const bool whole = p.whole;
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !std::isfinite(x)) return "expected a number, got '" + text + "'";
        if (whole && (x != std::floor(x) || x < lo || x > hi))
          return "must be a whole number from " + gnum(lo) + " to " + gnum(hi) + ", got " + text;
        if (!whole && !(x > lo && x <= hi)) return "must be in (" + gnum(lo) + ", " + gnum(hi) + "], got " + text;
        return "";
      },
      whole ? "INT in [" + gnum(lo) + " - " + gnum(hi) + "]" : "in (" + gnum(lo) + ", " + gnum(hi) + "]");
}

}  // namespace

void refuseUnreadRunOptions(const CLI::App& cmd, const std::vector<Method>& methods, bool adaptive_inhouse) {
  for (const MethodParam& p : methodParams()) {
    if (!cmd.count(optionName(p))) continue;
    std::vector<std::string> takers;
    for (const MethodInfo& m : methodTable())
      if (m.takes(p.name)) takers.emplace_back(m.name);
    bool read = false;
    for (Method m : methods) read = read || info(m).takes(p.name);
    if (!read)
      throw std::invalid_argument(optionName(p) + ": no method of this run takes it (only " + joined(takers) + ")");
    if (p.read_when) {
      const MethodParam under = methodParam(p.read_when);
      const std::string option = optionName(under);
      const double value = cmd.count(option) ? cmd.get_option(option)->as<double>() : under.fallback;
      if (!(value > 0))
        throw std::invalid_argument(optionName(p) + ": read only with " + option + " > 0, and " + option + " is " + gnum(value));
    }
  }
  if (cmd.count("--no-step-retry") && !adaptive_inhouse)
    throw std::invalid_argument("--no-step-retry: only an adaptive in-house integrator retries a step, and this run has none");
}

void addRunOptions(CLI::App* cmd, RunArgs& g, const std::string& output_dt_help) {
  cmd->add_option("--t-end", g.t_end, "End time (s); default: the scene's simulate.t_end")->check(positiveFinite());
  cmd->add_option("--output-dt", g.output_dt, output_dt_help + "; default: the scene's simulate.output_dt")
      ->check(positiveFinite());
  cmd->add_flag("--allow-long-run", g.allow_long_run, "Run more than 1e8 fixed steps or 1e6 output samples (refused otherwise, as a likely typo)");
  cmd->add_flag("--no-step-retry", g.no_step_retry,
                "Adaptive integrators: end the run when the right-hand side fails at a trial stage (default: retry the "
                "step at a quarter of its size)");
  for (const MethodParam& p : methodParams()) {
    double& value = g.params[p.name] = p.fallback;
    cmd->add_option(optionName(p), value, p.help)->check(paramValidator(p))->capture_default_str();
  }
  std::vector<std::string> formulations;
  for (const FormulationInfo& f : formulationTable()) formulations.push_back(std::string(f.name) + ": " + f.summary);
  cmd->add_option("--formulation", g.formulation, "A mechanism's formulation (docs/theory.md §15): " + joined(formulations))
      ->check(CLI::IsMember([] {
        std::vector<std::string> n;
        for (const FormulationInfo& f : formulationTable()) n.emplace_back(f.name);
        return n;
      }()))
      ->capture_default_str();
  cmd->add_option("--baumgarte-alpha", g.loops.alpha, "A mechanism's Baumgarte alpha (1/s): G u' = -c - 2 alpha G u - beta^2 g")
      ->check(finiteRange(0.0, 1e12))
      ->capture_default_str();
  cmd->add_option("--baumgarte-beta", g.loops.beta, "A mechanism's Baumgarte beta (1/s)")->check(finiteRange(0.0, 1e12))->capture_default_str();
  cmd->add_option("--al-penalty-ratio", g.loops.penalty_ratio,
                  "The augmented Lagrangian's penalty: its iteration matrix weighs the loops this many times the inertia "
                  "(docs/theory.md (M13)); with --formulation augmented-lagrangian only")
      ->check(finiteRange(1.0, 1e10))
      ->capture_default_str();
  addProgressFlags(cmd);
}

void addProgressFlags(CLI::App* cmd) {
  auto* on = cmd->add_flag_callback("--progress", [] { setProgressMode(ProgressMode::On); },
                                    "Show the progress of runs longer than 2 s even when stderr is not a terminal");
  auto* off = cmd->add_flag_callback("--no-progress", [] { setProgressMode(ProgressMode::Off); },
                                     "Never show the progress of long runs (default: on a terminal only)");
  on->excludes(off);
}

void refuseUnreadLoopOptions(const CLI::App& cmd, const Model& m) {
  for (const MethodParam& p : methodParams())  // an engine's stops' own
    if (p.limits_only && m.limited.empty() && cmd.count(optionName(p)))
      throw std::invalid_argument(optionName(p) + ": scene '" + m.name + "' has no joint limits");
  if (!m.loops.empty()) return;
  for (const char* option : {"--formulation", "--baumgarte-alpha", "--baumgarte-beta", "--al-penalty-ratio"})
    if (cmd.count(option)) throw std::invalid_argument(std::string(option) + ": scene '" + m.name + "' has no loops");
  for (const MethodParam& p : methodParams())  // an engine's closures' own
    if (p.loops_only && cmd.count(optionName(p)))
      throw std::invalid_argument(optionName(p) + ": scene '" + m.name + "' has no loops");
}

void refuseUnreadFormulationOptions(const CLI::App& cmd, const std::vector<Method>& methods, Integrator inhouse,
                                    Formulation f, const Model& m) {
  if (m.loops.empty()) return;  // refuseUnreadLoopOptions said it
  static const char* const kAll[] = {"--formulation", "--baumgarte-alpha", "--baumgarte-beta", "--al-penalty-ratio"};
  const bool any_inhouse = std::any_of(methods.begin(), methods.end(), [](Method x) { return info(x).engine == Engine::InHouse; });
  for (const char* option : kAll) {
    if (!cmd.count(option)) continue;
    if (!any_inhouse)
      throw std::invalid_argument(std::string(option) + ": no in-house method runs (" + methodName(methods.front()) +
                                  " closes the loops its own way)");
    if (info(inhouse).dae)
      throw std::invalid_argument(std::string(option) + ": integrator " + integratorName(inhouse) +
                                  " integrates the loops as its own index-2 DAE, no formulation of ours");
  }
  const FormulationInfo& row = formulationRow(f);
  if (cmd.count("--al-penalty-ratio") && f != Formulation::AugmentedLagrangian)
    throw std::invalid_argument("--al-penalty-ratio: read by --formulation augmented-lagrangian only");
  if (row.brings_integrator)
    for (const char* option : {"--baumgarte-alpha", "--baumgarte-beta"})
      if (cmd.count(option))
        throw std::invalid_argument(std::string(option) + ": the formulation " + row.name + " reads no Baumgarte values");
  if (cmd.count("--formulation") && row.brings_integrator && row.own_integrator != inhouse)
    throw std::invalid_argument(std::string("--formulation ") + row.name + ": it runs under its own integrator " +
                                integratorName(row.own_integrator) + ", not " + integratorName(inhouse) + " (--integrator " +
                                integratorName(row.own_integrator) + ")");
}

void addSceneArg(CLI::App* cmd, SceneArg& s) {
  cmd->add_option("scene", s.path, "Scene file: eigenmass-scene/1 JSON, or a URDF robot (.urdf; docs/urdf.md)")->required();
  cmd->add_flag("--balance-inertia", s.urdf.balance_inertia,
                "URDF: set principal moments that violate the triangle inequality to their mean (MuJoCo's balanceinertia), "
                "noted in the outputs; refused otherwise");
  cmd->add_flag("--floating-base", s.urdf.floating_base,
                "URDF: free the root link: it moves on a free joint named floating_base (floating_base_2, ... where the URDF has that name; 6 speeds) instead of being "
                "held by the ground");
  cmd->add_option("--lock-joint", s.urdf.lock_joints,
                  "URDF: hold this joint at zero, merged like a fixed joint (repeatable or comma-separated)")
      ->delimiter(',');
  cmd->add_flag("--urdf-damping", s.urdf.damping,
                "URDF: import each joint's <dynamics damping> as a joint damper (a nonzero <dynamics friction> is then refused unless --urdf-ignore-friction)");
  cmd->add_flag("--urdf-ignore-friction", s.urdf.ignore_friction, "URDF: with --urdf-damping, run without the <dynamics friction> it cannot model, noted");
  cmd->add_option("--urdf-limits", s.urdf.limits_restitution,
                  "URDF: import each revolute and prismatic joint's <limit lower upper> as stops of this restitution (0 to 1; docs/theory.md §17)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--control", s.urdf.control_file,
                  "URDF: joint controllers by URDF joint name, an eigenmass-control/1 file (docs/scene-format.md, joint.control; "
                  "\"effort\": \"urdf\" clamps at the joint's <limit effort>)");
  cmd->add_flag("--assemble", s.assemble,
                "A mechanism: project the written start onto the loops (q0 by Gauss-Newton in A's metric, then u0), as the "
                "scene's simulate.assemble does, and say by how much in the outputs; without it an open start is refused");
}

void progress(const std::string& what) {
  if (progressMode() != ProgressMode::Off) std::fprintf(stderr, "running %s ...\n", what.c_str());
}

CLI::Validator methodValidator() {
  // A plugin's or a recorded run's name is not in the table when the options are read: say how it is named.
  return CLI::Validator(
      [](std::string& v) {
        Method m;
        if (findMethod(v, m)) return std::string();
        std::string all;
        for (const std::string& n : methodNames()) all += (all.empty() ? "" : ",") + n;
        return v + " not in {" + all + "} (a plugin's or a recorded run's method is named by --plugin NAME=lib.so or --run "
                                    "NAME=run.csv, and runs by that alone)";
      },
      "METHOD");
}
CLI::Validator integratorValidator() { return CLI::IsMember(integratorNames()); }
CLI::Validator integratorValidator(Engine engine) { return CLI::IsMember(integratorNames(engine)); }

std::string helpWithNames(const std::string& text, const std::vector<std::string>& names) {
  return text + ": " + joined(names);
}

std::vector<std::string> OutsideArgs::load(const Scene& scene) const {
  if (plugin_timeout > 0) setPluginTimeout(plugin_timeout);
  std::vector<std::string> names;
  const auto named = [](const std::string& option, const std::exception& e) {
    return std::invalid_argument(option + ": " + e.what());
  };
  for (const std::string& v : plugins) {
    const auto [name, path] = splitNamedFile("--plugin", v);
    try {
      probePlugin(addPlugin(name, path), scene.model);
    } catch (const std::exception& e) {
      throw named("--plugin", e);
    }
    names.push_back(name);
  }
  for (const std::string& v : runs) {
    const auto [name, path] = splitNamedFile("--run", v);
    try {
      addRecordedRun(name, path, scene.model);
    } catch (const std::exception& e) {
      throw named("--run", e);
    }
    names.push_back(name);
  }
  return names;
}

std::vector<std::string> OutsideArgs::files() const {
  std::vector<std::string> f;
  for (const auto* list : {&plugins, &runs})
    for (const std::string& v : *list)
      if (const size_t eq = v.find('='); eq != std::string::npos) f.push_back(v.substr(eq + 1));
  return f;
}

void addOutsideOptions(CLI::App* cmd, OutsideArgs& o, bool with_runs) {
  CLI::Option* plugin = cmd->add_option("--plugin", o.plugins,
                  "A method from outside: NAME=path/libx.so, a library with eigenmass_plugin.h's calls, run under the "
                  "in-house integrators as method NAME (repeatable; docs/plugins.md)");
  // The watch looks at a child every kPluginWatch s: a shorter timeout could not be kept.
  cmd->add_option("--plugin-timeout", o.plugin_timeout,
                  "Seconds a plugin's call may take before its run counts as hung (default " + gnum(kPluginTimeout) + ", from " +
                      gnum(kPluginWatch) + ", the watch's period, to " + gnum(kPluginTimeoutMax) + "); with --plugin only")
      ->check(finiteRange(kPluginWatch, kPluginTimeoutMax))
      ->needs(plugin);
  if (with_runs)
    cmd->add_option("--run", o.runs,
                    "A run made elsewhere: NAME=FILE.csv, joint coordinates or body poses (docs/report-format.md, "
                    "\"Outside runs\"), judged as method NAME (repeatable)");
}

}  // namespace em::cli
