#include "compare/gate.hpp"

#include "io/json_input.hpp"
#include "io/run_spec_json.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace em {

namespace {

using json = nlohmann::json;

// The last is a mechanism's: its loops' largest position violation (m or rad) over the run's samples, by our g(q).
const char* kMetrics[] = {"max_pose_error_rad", "max_position_error_m", "energy_error_max", "max_loop_violation"};

// Largest value of a per-sample series over t <= horizon.
double maxUpTo(const std::vector<double>& t, const std::vector<double>& v, double horizon) {
  double m = 0;
  for (size_t k = 0; k < v.size() && t[k] <= horizon * (1 + 1e-12); ++k) {
    if (std::isnan(v[k])) return NAN;
    m = std::max(m, v[k]);
  }
  return m;
}

const std::vector<double>& seriesOf(const MethodMetrics& m, const std::string& metric) {
  if (metric == "max_pose_error_rad") return m.series.pose_rad;
  if (metric == "max_position_error_m") return m.series.position_m;
  return m.series.energy_rel;
}

// The in-house integrator and its dt or tolerance that a scene's bounds hold for.
RunSpec inhouseSettings(const json& run, const std::string& path) {
  onlyKeys(run, path, {"integrator", "dt", "tolerance"});
  RunSpec s;
  const std::string name = stringAt(requireKey(run, path, "integrator"), jsonPath(path, "integrator"));
  if (!findIntegrator(name, s.integrator) || !info(s.integrator).runs(Engine::InHouse))
    throw InputError(jsonPath(path, "integrator"),
                     "unknown in-house integrator '" + printable(name, 40) + "' (" + joined(integratorNames(Engine::InHouse)) + ")");
  const std::string key = settingKeyIn(run, path, s.integrator);
  s.setSetting(positiveAt(requireKey(run, path, key.c_str()), jsonPath(path, key)));
  return s;
}

// One scene's bounds: {"horizon_s", "inhouse", "methods": {method: {metric: {"value", "reason"}}}}.
SceneTolerances sceneTolerances(const json& s, const std::string& sp) {
  onlyKeys(s, sp, {"horizon_s", "inhouse", "methods"});
  SceneTolerances st;
  st.horizon_s = positiveAt(requireKey(s, sp, "horizon_s"), jsonPath(sp, "horizon_s"));
  st.inhouse = inhouseSettings(requireKey(s, sp, "inhouse"), jsonPath(sp, "inhouse"));
  const std::string msp = jsonPath(sp, "methods");
  const json& methods = requireKey(s, sp, "methods");
  if (!methods.is_object()) throw InputError(msp, "expected an object");
  for (auto& [method, bounds] : methods.items()) {
    const std::string mp = jsonPath(msp, method);
    Method id;
    if (!findMethod(method, id)) throw InputError(mp, "unknown method (" + joined(methodNames()) + ")");
    if (!bounds.is_object()) throw InputError(mp, "expected an object");
    for (auto& [metric, b] : bounds.items()) {
      const std::string bp = jsonPath(mp, metric);
      if (std::find(std::begin(kMetrics), std::end(kMetrics), metric) == std::end(kMetrics))
        throw InputError(bp, "unknown metric (max_pose_error_rad, max_position_error_m, energy_error_max, max_loop_violation)");
      onlyKeys(b, bp, {"value", "reason"});
      const std::string reason = b.contains("reason") ? stringAt(b["reason"], jsonPath(bp, "reason")) : "";
      if (reason.empty()) throw InputError(jsonPath(bp, "reason"), "every bound needs a one-line reason");
      st.methods[method].push_back({metric, positiveAt(requireKey(b, bp, "value"), jsonPath(bp, "value")), reason});
    }
  }
  return st;
}

// The run was made with the integrator and the dt or tolerance the bounds were set for.
bool sameSettings(const RunSpec& ran, const RunSpec& file) {
  return ran.integrator == file.integrator && ran.setting() == file.setting();
}

}  // namespace

Tolerances loadTolerances(const std::string& file) {
  const json doc = readJsonFile(file, "tolerance file");  // strict: a duplicate key is an error, not the last one
  try {
    onlyKeys(doc, "", {"format", "scenes"});
    if (stringAt(requireKey(doc, "", "format"), "format") != "eigenmass-tolerances/1")
      throw InputError("format", "expected \"eigenmass-tolerances/1\"");
    const json& scenes = requireKey(doc, "", "scenes");
    if (!scenes.is_object()) throw InputError("scenes", "expected an object");
    Tolerances t;
    for (auto& [scene, s] : scenes.items()) t.scenes[scene] = sceneTolerances(s, jsonPath("scenes", scene));
    return t;
  } catch (const InputError& e) {
    throw std::runtime_error(file + ": " + e.what());
  }
}

GateResult evaluateGate(const ComparisonResult& r, const Tolerances& tol) {
  GateResult g;
  auto it = tol.scenes.find(r.scene_name);
  if (it == tol.scenes.end()) {
    g.passed = false;
    g.checks.push_back({"*", "scene", "", "no tolerances for scene '" + r.scene_name + "'", 0, 0, 0, false});
    return g;
  }
  const SceneTolerances& st = it->second;
  for (const auto& [method, bounds] : st.methods) {
    const auto m = std::find_if(r.metrics.begin(), r.metrics.end(), [&](const MethodMetrics& x) { return x.name() == method; });
    if (m == r.metrics.end()) continue;  // not run this time
    for (const Bound& b : bounds) {
      GateCheck c{method, b.metric, b.reason, "", 0, b.value, st.horizon_s, false};
      if (b.metric == "max_loop_violation") {  // over the whole run (the comparison's horizon is the gate's)
        c.value = m->has_loops ? std::max(m->loops.position_m, m->loops.position_rad) : NAN;
      } else {
        c.value = maxUpTo(m->series.t, seriesOf(*m, b.metric), st.horizon_s);
      }
      const bool covers = !m->series.t.empty() && m->series.t.back() >= st.horizon_s * (1 - 1e-12);
      if (m->run.engine() == Engine::InHouse && !sameSettings(m->run, st.inhouse))
        c.note = std::string("run with other in-house integrator settings than the tolerance file's (") +
                 integratorName(st.inhouse.integrator) + (st.inhouse.fixedStep() ? " dt " : " tol ") +
                 gnum(st.inhouse.setting()) + ")";
      else if (m->failed() && m->failure_time <= st.horizon_s)
        c.note = "method failed at t = " + gnum(m->failure_time) + " s: " + m->failure;
      else if (!covers)
        c.note = "run shorter than the horizon";
      if (c.note.empty() && std::isnan(c.value)) c.note = "no loops measured (a scene without loops)";
      c.passed = c.note.empty() && c.value <= c.bound;
      g.passed = g.passed && c.passed;
      g.checks.push_back(c);
    }
  }
  return g;
}

json gateJson(const GateResult& g) {
  json checks = json::array();
  for (const GateCheck& c : g.checks)
    checks.push_back({{"method", c.method},
                      {"metric", c.metric},
                      {"value", std::isfinite(c.value) ? json(c.value) : json(nullptr)},
                      {"bound", c.bound},
                      {"horizon_s", c.horizon_s},
                      {"passed", c.passed},
                      {"reason", c.reason},
                      {"note", c.note}});
  return {{"passed", g.passed}, {"checks", checks}};
}

std::string brokenChecks(const GateResult& g) {
  std::ostringstream o;
  for (const GateCheck& c : g.checks) {
    if (c.passed) continue;
    if (c.method == "*") {  // the scene itself has no bounds: no value to print against one
      o << "gate broken: " << c.note << "\n";
      continue;
    }
    o << "gate broken: " << c.method << " " << c.metric << " = " << c.value << " > " << c.bound << " over "
      << c.horizon_s << " s" << (c.note.empty() ? "" : " (" + c.note + ")") << "\n";
  }
  return o.str();
}

}  // namespace em
