#include "compare/comparison.hpp"

#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace em {

CompareOptions::CompareOptions() {
  inhouse.method = "classical";
  inhouse.integrator = "rk4";
  inhouse.dt = 1e-3;
  simbody.method = "simbody";
  simbody.integrator = "rkmerson";
  simbody.tol = 1e-6;
  reference.method = "simbody";
  reference.integrator = "rkmerson";
  reference.tol = 1e-10;
}

ComparisonResult compareRuns(const Trajectory& reference, const Trajectory& tight, std::vector<Trajectory> runs,
                             const CompareOptions& opt) {
  ComparisonResult r;
  r.options = opt;
  r.reference = reference;
  r.tight = tight;
  r.horizon = referenceHorizon(reference, tight, opt.thresholds);
  r.energy_scale = energyScale(reference);
  r.reference_metrics = compareRun(reference, reference, opt.thresholds, r.horizon, r.energy_scale);
  r.runs = std::move(runs);
  for (const Trajectory& t : r.runs) r.metrics.push_back(compareRun(t, reference, opt.thresholds, r.horizon, r.energy_scale));
  return r;
}

ComparisonResult runComparison(const Model& m, const std::string& scene_file, const CompareOptions& opt,
                               void (*progress)(const std::string&)) {
  if (opt.thresholds.empty()) throw std::invalid_argument("at least one threshold is needed");
  for (double th : opt.thresholds)
    if (!(th > 0)) throw std::invalid_argument("thresholds must be > 0");
  auto withGrid = [&](RunSpec s) {
    s.t_end = opt.t_end;
    s.output_dt = opt.output_dt;
    return s;
  };
  auto run = [&](const RunSpec& s, const std::string& label) {
    if (progress) progress(label);
    return runMethod(m, withGrid(s));
  };
  // Validate every method name before spending time on the reference.
  for (const auto& name : opt.methods) requireKnownMethod(name);
  const Trajectory ref = run(opt.reference, "reference " + opt.reference.method);
  RunSpec tight_spec = opt.reference;
  tight_spec.tol = opt.reference.tol / opt.tight_factor;
  const Trajectory tight = run(tight_spec, "horizon run (tolerance / " + std::to_string(int(opt.tight_factor)) + ")");
  std::vector<Trajectory> runs;
  for (const auto& name : opt.methods) {
    RunSpec s = name == "simbody" ? opt.simbody : opt.inhouse;
    s.method = name;
    runs.push_back(run(s, name));
  }
  ComparisonResult r = compareRuns(ref, tight, std::move(runs), opt);
  r.scene_name = m.name;
  r.scene_file = scene_file;
  r.nq = m.nq;
  r.nu = m.nu;
  r.bodies = m.n();
  r.t_end = opt.t_end > 0 ? opt.t_end : m.t_end;
  r.output_dt = opt.output_dt > 0 ? opt.output_dt : m.output_dt;
  return r;
}

namespace {
std::string timeOrDash(const std::optional<double>& t, bool meaningful) {
  if (!t) return "-";
  char b[32];
  std::snprintf(b, sizeof b, "%.2f%s", *t, meaningful ? "" : "*");
  return b;
}
}  // namespace

std::string summaryTable(const ComparisonResult& r) {
  std::ostringstream o;
  char line[256];
  std::snprintf(line, sizeof line, "%-18s %-7s", "method", "status");
  o << line;
  for (const char* kind : {"pose", "joint"})
    for (double th : r.options.thresholds) {
      std::snprintf(line, sizeof line, " %12s", (std::string(kind) + ">" + gnum(th)).c_str());
      o << line;
    }
  std::snprintf(line, sizeof line, " %12s %12s %10s %10s\n", "max pose rad", "max dE/Escl", "steps", "CPU s");
  o << line;
  auto row = [&](const MethodMetrics& m, const std::string& name) {
    std::snprintf(line, sizeof line, "%-18s %-7s", name.c_str(), m.status.c_str());
    o << line;
    for (size_t i = 0; i < m.divergence_time_s.size(); ++i) {
      std::snprintf(line, sizeof line, " %12s", timeOrDash(m.divergence_time_s[i], m.divergence_meaningful[i]).c_str());
      o << line;
    }
    for (const auto& t : m.coord_divergence_time_s) {
      std::snprintf(line, sizeof line, " %12s", timeOrDash(t, true).c_str());
      o << line;
    }
    std::snprintf(line, sizeof line, " %12.3e %12.3e %10ld %10.3f\n", m.pose.value, m.energy.value, m.steps, m.run_time_s);
    o << line;
  };
  for (const MethodMetrics& m : r.metrics) row(m, m.name);
  o << "reference: " << r.reference.method << "/" << r.reference.integrator << " tol " << r.options.reference.tol;
  if (r.reference.failed())
    o << " FAILED at t = " << r.reference.failure_time << " s: " << r.reference.failure
      << " (errors are measured against its samples only)";
  o << "; horizon (reference vs tol/" << r.options.tight_factor << "):";
  for (size_t i = 0; i < r.horizon.size(); ++i)
    o << " " << r.options.thresholds[i] << " rad " << (r.horizon[i] ? std::to_string(*r.horizon[i]) + " s" : "not within t_end");
  o << "\n";
  for (const MethodMetrics& m : r.metrics)
    if (m.status != "ok") o << m.name << " failed at t = " << (m.failure_time ? *m.failure_time : 0) << " s: " << m.failure << "\n";
  o << "pose>x / joint>x: first time (s) the largest body rotation error / joint-angle error against the reference\n"
       "exceeds x rad (- never; * at or beyond the reference horizon, not meaningful).\n"
       "dE/Escl = |E(t) - E(0)| / "
    << r.energy_scale << " J (the reference's largest kinetic energy).\n";
  return o.str();
}

}  // namespace em
