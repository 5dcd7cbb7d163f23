#include "compare/report.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "compare/provenance.hpp"
#include "outside/plugin.hpp"
#include "outside/recorded.hpp"
#include "io/atomic_file.hpp"
#include "io/run_spec_json.hpp"

namespace em {

namespace {

using json = nlohmann::json;


json peak(const Peak& p) { return {{"value", finiteOrNull(p.value)}, {"t", p.t}}; }

// How an exponent was measured, with its windows (docs/report-format.md).
json lyapunovJson(const std::optional<Lyapunov>& l, const LyapunovOptions& o, const char* kind) {
  if (!l) return nullptr;
  json windows = json::array();
  for (double w : l->windows) windows.push_back(finiteOrNull(w));
  return {{"kind", kind},
          {"method", "Benettin twin: classical rk4, separation d0 in (q, u) renormalized every renorm_s"},
          {"dt", o.dt}, {"d0", o.d0}, {"renorm_s", o.renorm_s}, {"window_s", o.window_s},
          {"t_s", l->t_stop}, {"completed", l->ok}, {"per_s", finiteOrNull(l->per_s)},
          {"uncertainty_per_s", finiteOrNull(l->uncertainty_per_s)},
          {"windows_std_per_s", finiteOrNull(l->windows_std_per_s)}, {"windows_per_s", windows}};
}

// The long-run exponent, or how to ask for it.
json lyapunovLongJson(const ComparisonResult& r) {
  if (!r.lyapunov_long) return {{"not_measured", "compare --lyapunov-long T measures it over T s"}};
  json j = lyapunovJson(r.lyapunov_long, longRunOptions(r.options.lyapunov_long_s),
                        "long-run: over a horizon well beyond the run; uncertainty the standard error of its block means");
  if (const auto& st = r.lyapunov_long_starts) {
    json each = json::array();
    for (const Lyapunov& l : st->starts) each.push_back({{"per_s", finiteOrNull(l.per_s)}, {"completed", l.ok}, {"t_s", l.t_stop}});
    j["starts"] = {{"how", "the scene's start and starts - 1 neighbours, q0 and u0 displaced by sigma N(0, 1) per coordinate "
                           "(SplitMix64 seeds seed + 1, seed + 2, ...; solver/perturb.hpp), each measured as above"},
                   {"n", st->starts.size()}, {"sigma", st->sigma}, {"seed", st->seed}, {"completed", st->completed},
                   {"mean_per_s", finiteOrNull(st->mean_per_s)}, {"spread_per_s", finiteOrNull(st->spread_per_s)},
                   {"each", each}};
  }
  return j;
}

json perThreshold(const std::vector<double>& th, const std::vector<std::optional<double>>& v) {
  json o = json::object();
  for (size_t i = 0; i < th.size(); ++i) o[thresholdKey(th[i])] = orNull(v[i]);
  return o;
}

// Where a method from outside came from (outside/): null for ours and the engines'.
json outsideSource(Method method) {
  json from = pluginSource(method);
  return from.is_null() ? recordedSource(method) : from;
}

json methodJson(const MethodMetrics& m, const std::vector<double>& th) {
  json j = {{"name", m.name()},
            {"integrator", integratorName(m.run.integrator)},
            {"status", outcomeName(m.status())},
            {"outcome", outcomeName(m.outcome)},
            {"failure", failureJson(m)},
            {"run_time_s", m.run_time_s},
            {"steps", m.steps},
            {"grid_cut_steps", gridCutSteps(m, m.run) ? json(*gridCutSteps(m, m.run)) : json(nullptr)},
            {"rhs_evals", m.rhs_evals},
            {"step_retries", m.step_retries},
            {"max_pose_error_rad", finiteOrNull(m.pose.value)},
            {"max_pose_error_t", m.pose.t},
            {"max_position_error_m", finiteOrNull(m.position.value)},
            {"max_coordinate_error_rad", m.coords_shared ? finiteOrNull(m.coord.value) : json(nullptr)},
            {"divergence_time_s", perThreshold(th, m.divergence_time_s)},
            {"coordinate_divergence_time_s", perThreshold(th, m.coord_divergence_time_s)},
            {"energy_error_max", finiteOrNull(m.energy.value)},
            {"energy_error_max_t", m.energy.t},
            {"energy_error_final", finiteOrNull(m.energy_error_final)},
            {"dissipated_final_J", finiteOrNull(m.dissipated_final)},
            {"max_joint_separation_m", finiteOrNull(m.max_joint_separation)}};
  putSetting(j, m.run);
  if (m.has_loops) j["loops"] = loopsJson(m, m.run);
  if (m.tracking)  // docs/report-format.md: the PD targets' tracking
    j["tracking"] = {{"max", m.tracking->max}, {"max_t", m.tracking->max_t}, {"coordinate", m.tracking->worst}, {"rms", m.tracking->rms},
                     {"how", "|q - q*(t)| over the PD-controlled coordinates at the output samples (rad; m for a slide)"}};
  if (const std::optional<ImpactCheck>& c = m.impact_check)  // docs/report-format.md: the stops against the reference's
    j["impacts"] = {{"count", c->count}, {"reference_count", c->reference_count}, {"compared", c->compared},
                    {"time_error_max_s", c->time_error_max}, {"rebound_error_max", c->rebound_error_max},
                    {"overshoot_max", c->overshoot_max}, {"beyond_stop_max_s", c->duration_max},
                    {"first_time_error_s", finiteOrNull(c->first_time_error)}, {"first_rebound_error", finiteOrNull(c->first_rebound_error)},
                    {"how", "the run's k-th impact against the reference's k-th (same coordinate) over the first `compared`: "
                            "|t - t_ref| and |u_after - u_after_ref| (rad/s or m/s); an engine's impact is its crossing of the stop, "
                            "its rebound the speed at the first step back inside; overshoot (rad or m) and time beyond the stop"}};
  if (json from = outsideSource(m.run.method); !from.is_null()) {  // a plugin's or a recorded run's
    j["source"] = from;
    j["colour"] = methodColour(m.run.method);  // plot's process does not know the method
  }
  json meaningful = json::object();
  for (size_t i = 0; i < th.size(); ++i)
    meaningful[thresholdKey(th[i])] = m.divergence_time_s[i] ? json(bool(m.divergence_meaningful[i])) : json(nullptr);
  j["divergence_meaningful"] = meaningful;
  const MethodInfo& row = info(m.run.method);
  for (const MethodParam& p : row.params) {  // the row's own options, as run (an engine's: its closures')
    if (p.loops_only && !m.has_loops) continue;  // not read on a tree
    if (p.limits_only && !m.impact_check) continue;  // not read without stops
    const double v = row.param(p.name, m.run.options);
    j[p.name] = p.whole ? json(static_cast<long>(v)) : json(v);
  }
  if (!m.has_diagnostics) {
    j["diagnostics"] = nullptr;
    return j;
  }
  j["diagnostics"] = {{"orthogonality_error_max", peak(m.orth_err)},
                      {"offdiag_rel_max", peak(m.offdiag_rel)},
                      {"inverse_error_max", peak(m.inv_err)},
                      {"max_abs_Omega", finiteOrNull(m.eigen.max_abs_Omega)},
                      {"max_abs_Omega_sampled", peak(m.max_Omega)},
                      {"min_eigen_gap", finiteOrNull(m.eigen.min_gap)},
                      {"min_eigen_gap_t", m.eigen.min_gap_time},
                      {"jacobi",
                       {{"sweeps", m.eigen.jacobi_sweeps},
                        {"rotations", m.eigen.jacobi_rotations},
                        {"steps_with_at_most_one_sweep", m.eigen.jacobi_single_sweep_steps},
                        {"max_sweeps_in_a_step", m.eigen.jacobi_max_sweeps}}},
                      {"block_merges", m.eigen.block_merges},
                      {"block_splits", m.eigen.block_splits}};
  return j;
}

// Every k-th sample so that at most max_points remain (the last one always kept).
json decimated(const std::vector<double>& v, size_t stride) {
  json a = json::array();
  for (size_t k = 0; k < v.size(); k += stride) a.push_back(finiteOrNull(v[k]));
  if (!v.empty() && (v.size() - 1) % stride) a.push_back(finiteOrNull(v.back()));
  return a;
}

// The angle coordinate some run leaves the reference on first by the largest
// threshold (the paper's Fig. 3 shows such an angle); the first angle when none
// leaves; q_0 when no coordinate is an angle.
int figureCoordinate(const ComparisonResult& r) {
  const Trajectory& ref = r.reference;
  if (ref.angle_coords.empty()) return 0;
  const double th = *std::max_element(r.options.thresholds.begin(), r.options.thresholds.end());
  int best = ref.angle_coords.front();
  size_t first = SIZE_MAX;  // sample index of the earliest exceedance
  for (const Trajectory& tr : r.runs)
    for (int i : ref.angle_coords)
      for (size_t k = 0; k < std::min({tr.q.size(), ref.q.size(), first}); ++k)
        if (i < tr.q[k].size() && std::abs(tr.q[k][i] - ref.q[k][i]) > th) {
          first = k, best = i;
          break;
        }
  return best;
}

// That coordinate against time for the reference and every run, on the series grid.
json coordinateSeries(const ComparisonResult& r, size_t stride) {
  const Trajectory& ref = r.reference;
  if (ref.q_names.empty()) return nullptr;
  const int i = figureCoordinate(r);
  const auto column = [&](const Trajectory& tr) {
    std::vector<double> v;  // (samples)
    for (const Eigen::VectorXd& q : tr.q) v.push_back(q[i]);
    return decimated(v, stride);
  };
  json j = {{"name", ref.q_names[i]}, {"index", i}, {"reference", column(ref)}, {"methods", json::object()}};
  for (const Trajectory& tr : r.runs) j["methods"][tr.method()] = column(tr);
  return j;
}

json seriesJson(const ComparisonResult& r, size_t stride) {
  json series = {{"t", decimated(r.reference.t, stride)}, {"stride", stride}, {"methods", json::object()}};
  for (const MethodMetrics& m : r.metrics)
    series["methods"][m.name()] = {{"pose_error_rad", decimated(m.series.pose_rad, stride)},
                                 {"position_error_m", decimated(m.series.position_m, stride)},
                                 {"energy_error", decimated(m.series.energy_rel, stride)}};
  // The reference against its tighter twin: the floor below which no error is resolved.
  const ErrorSeries check = errorSeries(r.reference, r.tight, r.energy_scale);
  series["reference_check"] = {{"pose_error_rad", decimated(check.pose_rad, stride)}};
  series["coordinate"] = coordinateSeries(r, stride);
  return series;
}

}  // namespace

std::string thresholdKey(double th) {
  // Shortest scientific form that reads back exactly: 0.001 -> "1e-03".
  char buf[40];
  for (int digits = 0; digits < 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*e", digits, th);
    if (std::strtod(buf, nullptr) == th) break;
  }
  // Then "1e-3": no '+' or leading zeros in the exponent; '.' becomes 'p'
  // ("2p5e-3") so that no key holds pandas.json_normalize's separator.
  std::string key;
  const std::string s = buf;
  const size_t e = s.find('e');
  for (char c : s.substr(0, e)) key += c == '.' ? 'p' : c;
  const int exponent = std::atoi(s.c_str() + e + 1);
  return key + "e" + std::to_string(exponent);
}

// What each engine that ran does to this scene (engineSceneNote), by engine name.
json engineNotesJson(const ComparisonResult& r) {
  json j = json::object();
  for (const auto& [engine, note] : r.engine_notes) j[engine] = note;
  return j;
}

// The reference's sensitivity twin and the thresholds it makes ill-conditioned.
json sensitivityJson(const ComparisonResult& r) {
  if (!r.sensitivity)
    return r.options.sensitivity_twin ? json({{"not_measured", "a scene with loops: a displaced start would leave them open"}}) : json(nullptr);
  const Sensitivity& s = *r.sensitivity;
  json ill = json::array();
  for (double th : r.options.thresholds)
    if (illConditioned(s, th)) ill.push_back(th);
  return {{"how", "the reference again from a start displaced by sigma N(0, 1) on every coordinate and speed (seed " +
                      std::to_string(kSensitivitySeed) + "); amplification = max_pose_rad / sigma; round-off (" + gnum(kRoundoffScale) +
                      " relative) grows to amplification x " + gnum(kRoundoffScale) + " rad; a threshold is ill-conditioned where that exceeds " +
                      gnum(kRoundoffShare) + " of it, where the twin left the linear regime (max_pose_rad > " + gnum(kTwinLinearRad) +
                      " rad: the amplification is at least gap / sigma), or where the twin stopped"},
          {"sigma", s.sigma},
          {"max_pose_rad", finiteOrNull(s.max_pose_rad)},
          {"amplification", finiteOrNull(s.amplification())},
          {"roundoff_scale", kRoundoffScale},
          {"roundoff_pose_rad", finiteOrNull(s.roundoffPoseRad())},
          {"saturated", s.saturated()},
          {"failed_at_s", s.failed_at ? json(*s.failed_at) : json(nullptr)},
          {"ill_conditioned_at_rad", ill}};
}

// A mechanism's default reference that stopped before t_end (IDA at a
// singular position): why it was replaced, and its distance from the
// replacement over its own span (null where the reference ran as asked).
json stoppedReferenceJson(const ComparisonResult& r) {
  if (!r.stopped_reference) return nullptr;
  const Trajectory& ida = *r.stopped_reference;
  return {{"why", r.reference_note},
          {"checked_by", {{"method", ida.method()}, {"integrator", ida.integrator()}, {"tolerance", ida.run.tol},
                          {"until_s", ida.failure_time}, {"failure", ida.failure},
                          {"max_pose_rad", r.stopped_reference_metrics ? finiteOrNull(r.stopped_reference_metrics->pose.value) : json(nullptr)},
                          {"samples_checked", r.stopped_reference_metrics ? json(ida.t.size() - 1) : json(0)}}}};
}

// MuJoCo at a small step against the reference: the two independent engines' distance.
json secondEngineJson(const ComparisonResult& r) {
  if (!r.second_engine_metrics) return r.second_engine_skipped.empty() ? json(nullptr) : json({{"skipped", r.second_engine_skipped}});
  const Trajectory& t = *r.second_engine;
  const MethodMetrics& m = *r.second_engine_metrics;
  return {{"method", t.method()},          {"integrator", t.integrator()},
          {"dt", t.run.dt},                {"status", outcomeName(t.status())},
          {"failure", failureJson(m)},     {"max_pose_error_rad", finiteOrNull(m.pose.value)},
          {"max_position_error_m", finiteOrNull(m.position.value)},
          {"energy_error_max", finiteOrNull(m.energy.value)}, {"run_time_s", t.run_time_s}};
}

json makeReport(const ComparisonResult& r, const json& gate, int max_series_points) {
  const CompareOptions& o = r.options;
  json methods = json::array();
  for (const MethodMetrics& m : r.metrics) methods.push_back(methodJson(m, o.thresholds));
  const size_t n = r.reference.t.size();
  const size_t stride = std::max<size_t>(1, (n + max_series_points - 1) / std::max(1, max_series_points));
  const json series = seriesJson(r, stride);
  json horizon = perThreshold(o.thresholds, r.horizon);
  std::vector<std::string> names;
  for (Method m : o.methods) names.push_back(methodName(m));
  const RunSpec& ref = r.reference.run;
  json scene = {{"name", r.scene_name}, {"bodies", r.bodies}, {"nq", r.nq}, {"nu", r.nu}};
  scene.update(sceneSourceJson(r.scene_source));
  json options = {{"methods", names},
                  {"inhouse", runSpecJson(o.inhouse)},
                  {"t_end", r.t_end},
                  {"output_dt", r.output_dt},
                  {"thresholds_rad", o.thresholds},
                  {"energy_scale_J", r.energy_scale},
                  {"energy_scale_definition", r.energy_scale_definition}};
  for (const auto& entry : o.engines)  // one spec per engine, as its runs resolve it
    options[engineName(entry.first)] = runSpecJson(o.specFor(info(entry.first).method));
  if (!o.left_out.empty()) {  // engines that cannot take the scene, left out of the default methods
    json left = json::array();
    for (const auto& [method, why] : o.left_out) left.push_back({{"method", methodName(method)}, {"why", why}});
    options["methods_left_out"] = left;
  }
  return {{"format", "eigenmass-report/1"},
          {"scene", scene},
          {"options", options},
          {"reference",
           {{"engine", engineName(ref.engine())},
            {"method", r.reference.method()},
            {"integrator", r.reference.integrator()},
            {"tolerance", r.reference.run.settingKind() == SettingKind::Tolerance ? json(ref.tol) : json(nullptr)},
            {"dt", r.reference.run.settingKind() == SettingKind::Dt ? json(r.reference.run.dt) : json(nullptr)},
            {"horizon_tolerance", r.tight.run.settingKind() == SettingKind::Tolerance ? json(r.tight.run.tol) : json(nullptr)},
            {"horizon_dt", r.tight.run.settingKind() == SettingKind::Dt ? json(r.tight.run.dt) : json(nullptr)},
            {"horizon_s", horizon},
            {"check_max_pose_rad", finiteOrNull(r.reference_check_pose_rad)},
            {"status", outcomeName(r.reference.status())},
            {"failure", r.reference.failed() ? failureJson(r.reference_metrics) : json(nullptr)},
            {"run_time_s", r.reference.run_time_s},
            {"steps", r.reference.steps},
            {"grid_cut_steps", gridCutSteps(r.reference, r.reference.run) ? json(*gridCutSteps(r.reference, r.reference.run)) : json(nullptr)},
            {"rhs_evals", r.reference.rhs_evals},
            {"energy_error_max", finiteOrNull(r.reference_metrics.energy.value)},
            {"loops", r.reference_metrics.has_loops ? loopsJson(r.reference_metrics, r.reference.run) : json(nullptr)},
            {"lyapunov_per_s", r.lyapunov ? finiteOrNull(r.lyapunov->per_s) : json(nullptr)},
            {"lyapunov_uncertainty_per_s", r.lyapunov ? finiteOrNull(r.lyapunov->uncertainty_per_s) : json(nullptr)},
            {"lyapunov", lyapunovJson(r.lyapunov, LyapunovOptions(),
                                      "finite-time: over the run's grid; uncertainty the standard error of its 1-s windows, "
                                      "windows_std_per_s their spread")},
            {"lyapunov_long", lyapunovLongJson(r)},
            {"sensitivity_twin", sensitivityJson(r)},
            {"second_engine", secondEngineJson(r)},
            {"replaced", stoppedReferenceJson(r)}}},
          {"engine_notes", engineNotesJson(r)},
          {"methods", methods},
          {"series", series},
          {"gate", gate},
          {"provenance", provenance()}};
}

void writeJsonAtomic(const json& j, const std::string& path) {
  writeAtomic(path, "report", [&](std::ostream& out) { out << j.dump(2) << "\n"; });
}

json failureJson(const std::optional<double>& t, Failure kind, const std::string& cause, double cond_A) {
  return {{"t", t ? json(*t) : json(nullptr)},
          {"kind", failureName(kind)},
          {"cause", cause},
          {"cond_A", std::isfinite(cond_A) ? json(cond_A) : json(nullptr)}};
}

json failureJson(const MethodMetrics& m) {
  if (!m.failed()) return nullptr;
  return failureJson(m.failedAt(), m.failure_kind, m.failure, m.failure_cond_A);
}

}  // namespace em
