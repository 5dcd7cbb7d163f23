#include "compare/precision.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace em {

PrecisionOptions::PrecisionOptions() {
  reference.method = "simbody";
  reference.integrator = "rkmerson";
  reference.tol = 1e-10;
}

PrecisionResult runPrecision(const Model& m, const PrecisionOptions& opt, void (*progress)(const std::string&)) {
  if (opt.settings.empty()) throw std::invalid_argument("at least one step or tolerance is needed");
  for (double s : opt.settings)
    if (!(s > 0)) throw std::invalid_argument("steps and tolerances must be > 0");
  const bool fixed = opt.integrator == "rk4";
  for (const auto& method : opt.methods) requireKnownMethod(method);  // before the reference runs
  for (const auto& method : opt.methods)
    if (method == "simbody" && fixed)
      throw std::invalid_argument("simbody has no fixed-step integrator here: give an adaptive --integrator and tolerances");
  PrecisionResult r;
  r.scene_name = m.name;
  r.options = opt;
  r.t_end = opt.t_end > 0 ? opt.t_end : m.t_end;
  auto spec = [&](RunSpec s) {
    s.t_end = opt.t_end;
    s.output_dt = opt.output_dt;
    s.diagnostics = false;  // only errors and cost are wanted here
    return s;
  };
  if (progress) progress("reference " + opt.reference.method);
  r.reference = runMethod(m, spec(opt.reference));
  const double scale = energyScale(r.reference);
  for (const auto& method : opt.methods)
    for (double setting : opt.settings) {
      RunSpec s;
      s.method = method;
      s.integrator = method == "simbody" ? "rkmerson" : opt.integrator;
      (fixed ? s.dt : s.tol) = setting;
      if (progress) progress(method + " " + opt.integrator + " " + gnum(setting));
      const Trajectory t = runMethod(m, spec(s));
      r.points.push_back({method, s.integrator, setting, compareRun(t, r.reference, {}, {}, scale)});
    }
  return r;
}

std::string precisionTable(const PrecisionResult& r) {
  std::ostringstream o;
  char line[256];
  const bool fixed = r.options.integrator == "rk4";
  std::snprintf(line, sizeof line, "%-18s %-10s %-7s %14s %14s %10s %10s\n", "method", fixed ? "dt" : "tol", "status",
                "max pose rad", "max dE/Escl", "CPU s", "rhs evals");
  o << line;
  for (const PrecisionPoint& p : r.points) {
    const MethodMetrics& m = p.metrics;
    std::snprintf(line, sizeof line, "%-18s %-10s %-7s %14.3e %14.3e %10.3f %10ld\n", p.method.c_str(),
                  gnum(p.setting).c_str(), m.status.c_str(), m.pose.value, m.energy.value, m.run_time_s, m.rhs_evals);
    o << line;
  }
  o << "errors over 0.." << r.t_end << " s against " << r.reference.method << "/" << r.reference.integrator << " tol "
    << gnum(r.options.reference.tol) << "; a failed run's errors cover only its samples.\n";
  return o.str();
}

nlohmann::json precisionJson(const PrecisionResult& r) {
  using json = nlohmann::json;
  auto num = [](double x) { return std::isfinite(x) ? json(x) : json(nullptr); };
  json points = json::array();
  for (const PrecisionPoint& p : r.points) {
    const MethodMetrics& m = p.metrics;
    points.push_back({{"method", p.method},
                      {"integrator", p.integrator},
                      {p.integrator == "rk4" ? "step" : "tolerance", p.setting},
                      {"status", m.status},
                      {"failure", m.status == "ok" ? json(nullptr)
                                                   : json({{"t", m.failure_time ? json(*m.failure_time) : json(nullptr)},
                                                           {"cause", m.failure}})},
                      {"max_pose_error_rad", num(m.pose.value)},
                      {"max_position_error_m", num(m.position.value)},
                      {"energy_error_max", num(m.energy.value)},
                      {"run_time_s", m.run_time_s},
                      {"steps", m.steps},
                      {"rhs_evals", m.rhs_evals}});
  }
  return {{"format", "eigenmass-precision/1"},
          {"scene", r.scene_name},
          {"t_end", r.t_end},
          {"reference",
           {{"method", r.reference.method}, {"integrator", r.reference.integrator}, {"tolerance", r.options.reference.tol}}},
          {"points", points}};
}

}  // namespace em
