#include "compare/gate.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace em {

namespace {

using json = nlohmann::json;

const char* kMetrics[] = {"max_pose_error_rad", "max_position_error_m", "energy_error_max"};

[[noreturn]] void bad(const std::string& file, const std::string& path, const std::string& what) {
  throw std::runtime_error(file + ": " + path + ": " + what);
}

double positive(const json& v, const std::string& file, const std::string& path) {
  if (!v.is_number() || !(v.get<double>() > 0)) bad(file, path, "expected a positive number");
  return v.get<double>();
}

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
RunSpec inhouseSettings(const json& run, const std::string& file, const std::string& path) {
  if (!run.is_object() || !run.contains("integrator") || !run["integrator"].is_string())
    bad(file, path, "expected {\"integrator\": ..., \"dt\" or \"tolerance\": ...}");
  RunSpec s;
  const std::string name = run["integrator"].get<std::string>();
  if (!findIntegrator(name, s.integrator) || !info(s.integrator).runs(Engine::InHouse))
    bad(file, path + ".integrator", "unknown in-house integrator '" + name + "' (" + joined(integratorNames(Engine::InHouse)) + ")");
  if (s.fixedStep()) s.dt = positive(run.value("dt", json()), file, path + ".dt");
  else s.tol = positive(run.value("tolerance", json()), file, path + ".tolerance");
  return s;
}

// The run was made with the integrator and the dt or tolerance the bounds were set for.
bool sameSettings(const RunSpec& ran, const RunSpec& file) {
  return ran.integrator == file.integrator && ran.setting() == file.setting();
}

}  // namespace

Tolerances loadTolerances(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error(file + ": cannot open the tolerance file");
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::exception& e) {
    bad(file, "(document)", "invalid JSON");
  }
  if (!doc.is_object() || doc.value("format", "") != "eigenmass-tolerances/1")
    bad(file, "format", "expected \"eigenmass-tolerances/1\"");
  if (!doc.contains("scenes") || !doc["scenes"].is_object()) bad(file, "scenes", "expected an object");
  Tolerances t;
  for (auto& [scene, s] : doc["scenes"].items()) {
    const std::string sp = "scenes." + scene;
    if (!s.is_object()) bad(file, sp, "expected an object");
    SceneTolerances st;
    st.horizon_s = positive(s.value("horizon_s", json()), file, sp + ".horizon_s");
    st.inhouse = inhouseSettings(s.value("inhouse", json()), file, sp + ".inhouse");
    if (!s.contains("methods") || !s["methods"].is_object()) bad(file, sp + ".methods", "expected an object");
    for (auto& [method, bounds] : s["methods"].items()) {
      const std::string mp = sp + ".methods." + method;
      Method id;
      if (!findMethod(method, id)) bad(file, mp, "unknown method (" + joined(methodNames()) + ")");
      for (auto& [metric, b] : bounds.items()) {
        const std::string bp = mp + "." + metric;
        if (std::find(std::begin(kMetrics), std::end(kMetrics), metric) == std::end(kMetrics))
          bad(file, bp, "unknown metric (max_pose_error_rad, max_position_error_m, energy_error_max)");
        if (!b.is_object() || !b.contains("reason") || !b["reason"].is_string() || b["reason"].get<std::string>().empty())
          bad(file, bp + ".reason", "every bound needs a one-line reason");
        st.methods[method].push_back({metric, positive(b.value("value", json()), file, bp + ".value"),
                                      b["reason"].get<std::string>()});
      }
    }
    t.scenes[scene] = st;
  }
  return t;
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
      const std::vector<double>& s = seriesOf(*m, b.metric);
      c.value = maxUpTo(m->series.t, s, st.horizon_s);
      const bool covers = !m->series.t.empty() && m->series.t.back() >= st.horizon_s * (1 - 1e-12);
      if (m->run.engine() == Engine::InHouse && !sameSettings(m->run, st.inhouse))
        c.note = std::string("run with other in-house integrator settings than the tolerance file's (") +
                 integratorName(st.inhouse.integrator) + (st.inhouse.fixedStep() ? " dt " : " tol ") +
                 gnum(st.inhouse.setting()) + ")";
      else if (m->status != "ok" && m->failure_time && *m->failure_time <= st.horizon_s)
        c.note = "method failed at t = " + gnum(*m->failure_time) + " s: " + m->failure;
      else if (!covers)
        c.note = "run shorter than the horizon";
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
  for (const GateCheck& c : g.checks)
    if (!c.passed)
      o << "gate broken: " << c.method << " " << c.metric << " = " << c.value << " > " << c.bound << " over "
        << c.horizon_s << " s" << (c.note.empty() ? "" : " (" + c.note + ")") << "\n";
  return o.str();
}

}  // namespace em
