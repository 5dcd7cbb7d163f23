#include "compare/precision.hpp"

#include "io/run_spec_json.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "compare/provenance.hpp"
#include "compare/report.hpp"

namespace em {

RunSpec PrecisionOptions::specFor(Method method, double setting) const {
  RunSpec s;
  s.method = method;
  // Another engine runs the same scheme where it has it (mujoco: rk4), else its default.
  const Engine e = info(method).engine;
  s.integrator = info(integrator).runs(e) ? integrator : defaultIntegrator(e);
  s.setSetting(setting);
  s.diagnostics = false;  // only errors and cost are wanted here
  s.options = options;
  return s;
}

namespace {

// Every run of the sweep on the scene's grid, refused as a whole before any runs.
std::vector<CheckedRunSpec> precisionSpecs(const Scene& scene, const PrecisionOptions& opt) {
  if (opt.settings.empty()) throw std::invalid_argument("at least one step or tolerance is needed");
  for (double s : opt.settings)
    if (!(s > 0)) throw std::invalid_argument("steps and tolerances must be > 0");
  const bool fixed = info(opt.integrator).fixed_step;
  std::vector<RunSpec> specs;
  std::vector<CheckedRunSpec> runs;
  for (Method method : opt.methods) {
    if (info(opt.specFor(method, 1.0).integrator).fixed_step != fixed)
      throw std::invalid_argument(std::string(methodName(method)) + (fixed ? " has no fixed-step integrator here: give an "
                                                                             "adaptive --integrator and tolerances"
                                                                           : " has no adaptive integrator: give --integrator "
                                                                             "rk4 and steps"));
    for (double setting : opt.settings) specs.push_back(onGrid(opt.specFor(method, setting), scene, opt.grid));
  }
  for (const RunSpec& s : specs) {
    requireRunnable(s, scene.model);  // before the reference runs: what the run itself would refuse
    try {
      runs.push_back(checked(s));
    } catch (const SettingError& e) {
      throw e.field == "tol" || e.field == "dt" ? e.as("--settings") : e.as(e.option());
    }
  }
  return runs;
}

}  // namespace

PrecisionResult runPrecision(const Scene& scene, const PrecisionOptions& opt, void (*progress)(const std::string&)) {
  const std::vector<CheckedRunSpec> specs = precisionSpecs(scene, opt);
  RunSpec ref = onGrid(opt.reference, scene, opt.grid);
  ref.diagnostics = false;
  requireRunnable(ref, scene.model);
  const CheckedRunSpec ref_spec = [&] {
    try {
      return checked(ref);
    } catch (const SettingError& e) {
      throw e.as(e.option("reference-"));
    }
  }();
  PrecisionResult r;
  r.scene_name = scene.model.name;
  r.scene_source = scene.source;
  r.options = opt;
  r.t_end = ref.t_end;
  if (progress) progress(std::string("reference ") + methodName(ref.method));
  r.reference = runTrajectory(scene.model, ref_spec);
  const double scale = energyScale(r.reference);
  for (const CheckedRunSpec& s : specs) {
    if (progress) progress(std::string(methodName(s->method)) + " " + integratorName(s->integrator) + " " + gnum(s->setting()));
    r.points.push_back({measureRun(runTrajectory(scene.model, s), r.reference, {}, {}, scale)});
  }
  return r;
}

std::string precisionTable(const PrecisionResult& r) {
  std::ostringstream o;
  char line[256];
  const bool fixed = info(r.options.integrator).fixed_step;
  // The integrator column: an engine without --integrator's scheme runs its own (dart, ode under rk4), said on its row.
  std::snprintf(line, sizeof line, "%-18s %-16s %-10s %-18s %14s %14s %10s %10s\n", "method", "integrator", fixed ? "dt" : "tol",
                "status", "max pose rad", "max dE/Escl", "CPU s", "rhs evals");
  o << line;
  for (const PrecisionPoint& p : r.points) {
    const MethodMetrics& m = p.metrics;
    const std::string status = m.failed() ? std::string(outcomeName(m.status())) + " at " + gnum(m.failure_time, 3) + " s" : outcomeName(m.status());
    std::snprintf(line, sizeof line, "%-18s %-16s %-10s %-18s %14.3e %14.3e %10.3f %10ld\n", m.name().c_str(),
                  integratorName(m.run.integrator), gnum(m.run.setting()).c_str(), status.c_str(), m.pose.value, m.energy.value, m.run_time_s, m.rhs_evals);
    o << line;
  }
  o << "errors over 0.." << gnum(r.t_end) << " s against " << r.reference.method() << "/" << r.reference.integrator()
    << " tol " << gnum(r.reference.run.tol) << "; a failed run's errors cover only its samples.\n";
  return o.str();
}

nlohmann::json precisionJson(const PrecisionResult& r) {
  using json = nlohmann::json;
  json points = json::array();
  for (const PrecisionPoint& p : r.points) {
    const MethodMetrics& m = p.metrics;
    points.push_back({{"method", m.name()},
                      {"integrator", integratorName(m.run.integrator)},
                      {settingKindName(m.run.settingKind()), m.run.setting()},
                      {"status", outcomeName(m.status())},
                      {"failure", failureJson(m)},
                      {"max_pose_error_rad", finiteOrNull(m.pose.value)},
                      {"max_position_error_m", finiteOrNull(m.position.value)},
                      {"energy_error_max", finiteOrNull(m.energy.value)},
                      {"run_time_s", m.run_time_s},
                      {"steps", m.steps},
                      {"rhs_evals", m.rhs_evals}});
    // A mechanism's point: its loops' violation, rank and formulation, as a report's method (issue 73's doubtful list).
    if (m.has_loops) points.back()["loops"] = loopsJson(m, m.run);
  }
  return {{"format", "eigenmass-precision/1"},
          {"scene", r.scene_name},
          {"scene_source", sceneSourceJson(r.scene_source)},
          {"t_end", r.t_end},
          {"reference",
           {{"method", r.reference.method()}, {"integrator", r.reference.integrator()}, {"tolerance", r.reference.run.tol}}},
          {"points", points},
          {"provenance", provenance()}};
}

}  // namespace em
