// The merged results of a sweep: the case records, the CSV and the tables
// (docs/sweep.md, "Outputs").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "compare/report.hpp"
#include "sweep/sweep.hpp"
#include "io/atomic_file.hpp"
#include "io/json_input.hpp"

namespace em {

using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

// "pose_beyond_1e-3_s": the file key of the first time beyond kCaseThresholds[i].
std::string beyondKey(const char* what, size_t i) {
  return std::string(what) + "_beyond_" + thresholdKey(kCaseThresholds[i]) + "_s";
}


json eigenStatsJson(const EigenStats& e) {
  return {{"min_gap", finiteOrNull(e.min_gap)}, {"max_abs_Omega", e.max_abs_Omega}, {"jacobi_sweeps", e.jacobi_sweeps},
          {"block_merges", e.block_merges}, {"block_splits", e.block_splits}};
}

EigenStats eigenStatsFrom(const json& j) {
  EigenStats e;
  e.min_gap = numberFrom(j.at("min_gap"));
  e.max_abs_Omega = j.at("max_abs_Omega").get<double>();
  e.jacobi_sweeps = j.at("jacobi_sweeps").get<long>();
  e.block_merges = j.at("block_merges").get<long>();
  e.block_splits = j.at("block_splits").get<long>();
  return e;
}

// min_gap,max_abs_Omega,jacobi_sweeps,block_merges,block_splits (blank for other methods).
std::string eigenCells(const std::optional<EigenStats>& e) {
  if (!e) return ",,,,";
  return (std::isfinite(e->min_gap) ? gnum(e->min_gap, 17) : "") + "," + gnum(e->max_abs_Omega, 17) + "," +
         std::to_string(e->jacobi_sweeps) + "," + std::to_string(e->block_merges) + "," + std::to_string(e->block_splits);
}

std::vector<double> sorted(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v;
}

}  // namespace

double CaseRecord::cpuMedian() const {
  const std::vector<double> s = sorted(cpu_s);
  if (s.empty()) return NAN;
  return s.size() % 2 ? s[s.size() / 2] : 0.5 * (s[s.size() / 2 - 1] + s[s.size() / 2]);
}
double CaseRecord::cpuMin() const { return cpu_s.empty() ? NAN : *std::min_element(cpu_s.begin(), cpu_s.end()); }
double CaseRecord::cpuMax() const { return cpu_s.empty() ? NAN : *std::max_element(cpu_s.begin(), cpu_s.end()); }

json caseRecordJson(const CaseRecord& r) {
  json j = {{"name", r.name},         {"role", caseRoleName(r.role)},         {"member", r.member},
          {"scene", r.scene},       {"nu", r.nu},
          {"method", r.method},     {"integrator", r.integrator},
          {settingKindName(r.setting_kind), r.setting},
          {"status", outcomeName(r.status)},
          {"failure", r.status == Outcome::Ok ? json() : json{{"t", orNull(r.failure_time)}, {"kind", failureName(r.failure_kind)}, {"cause", r.failure}}},
          {"errors_against_reference", r.has_error},
          {"max_pose_error_rad", finiteOrNull(r.max_pose)},
          {"max_coord_error_rad", finiteOrNull(r.max_coord)},
          {"energy_error_max", finiteOrNull(r.max_energy)},
          {"cpu_s", r.cpu_s},       {"cpu_median_s", r.cpuMedian()},
          {"steps", r.steps},       {"rhs_evals", r.rhs_evals},
          {"grid_cut_steps", r.grid_cut_steps ? json(*r.grid_cut_steps) : json()},
          {"repeats_identical", r.repeats_identical},
          {"momentum_drift_p", orNull(r.momentum_p)},
          {"momentum_drift_H", orNull(r.momentum_H)},
          {"max_joint_separation_m", orNull(r.joint_separation)},
          {"loops_max_position_m", orNull(r.loop_position_m)},
          {"loops_max_position_rad", orNull(r.loop_position_rad)},
          {"loops_max_velocity_m_per_s", orNull(r.loop_velocity_m)},
          {"loops_max_velocity_rad_per_s", orNull(r.loop_velocity_rad)},
          {"benchmark_error_m", orNull(r.benchmark_error)},
          {"benchmark_error_t_s", orNull(r.benchmark_error_t)},
          {"eigen", r.eigen ? eigenStatsJson(*r.eigen) : json()},
          {"t0_s", orNull(r.t0)},
          {"pose_error_by_t0_rad", orNull(r.pose_by_t0)},
          {"lyapunov_per_s", orNull(r.lyapunov_per_s)},
          {"lyapunov_uncertainty_per_s", orNull(r.lyapunov_uncertainty_per_s)},
          {"sensitivity_twin_max_pose_rad", orNull(r.sensitivity_rad)},
          {"sensitivity_twin_failed_at_s", orNull(r.sensitivity_failed_at)}};
  for (size_t i = 0; i < kCaseThresholds.size(); ++i) {
    j[beyondKey("pose", i)] = orNull(r.pose_beyond[i]);
    j[beyondKey("coord", i)] = orNull(r.coord_beyond[i]);
  }
  if (!r.formulation.empty()) j["formulation"] = r.formulation;  // absent otherwise: older files read the same
  if (!r.tuning.empty()) j["tuning"] = r.tuning;
  return j;
}

CaseRecord readCaseRecord(const json& j, const std::string& source) {
  CaseRecord r;
  try {
    r.name = j.at("name").get<std::string>();
    const std::string role = j.at("role").get<std::string>();
    if (!findCaseRole(role, r.role)) throw std::invalid_argument("role '" + role + "'");
    r.member = j.value("member", 0);
    r.scene = j.at("scene").get<std::string>();
    r.nu = j.at("nu").get<int>();
    r.method = j.at("method").get<std::string>();
    r.integrator = j.at("integrator").get<std::string>();
    r.setting_kind = j.contains("dt") ? SettingKind::Dt : SettingKind::Tolerance;
    r.setting = j.at(settingKindName(r.setting_kind)).get<double>();
    const std::string status = j.at("status").get<std::string>();
    if (!findOutcome(status, r.status) || r.status == Outcome::Wrong) throw std::invalid_argument("status '" + status + "'");
    if (r.status != Outcome::Ok) {
      const json& f = j.at("failure");
      const std::string kind = f.at("kind").get<std::string>();
      if (!findFailure(kind, r.failure_kind)) throw std::invalid_argument("failure kind '" + kind + "'");
      r.failure = f.at("cause").get<std::string>();
      r.failure_time = optionalFrom(f.at("t"));
    }
    r.has_error = j.at("errors_against_reference").get<bool>();
    r.max_pose = numberFrom(j.at("max_pose_error_rad"));
    r.max_coord = numberFrom(j.at("max_coord_error_rad"));
    r.max_energy = numberFrom(j.at("energy_error_max"));
    for (size_t i = 0; i < kCaseThresholds.size(); ++i) {
      r.pose_beyond[i] = optionalFrom(j.at(beyondKey("pose", i)));
      r.coord_beyond[i] = optionalFrom(j.at(beyondKey("coord", i)));
    }
    r.cpu_s = j.at("cpu_s").get<std::vector<double>>();
    r.steps = j.at("steps").get<long>();
    r.rhs_evals = j.at("rhs_evals").get<long>();
    r.sensitivity_rad = optionalFrom(j.value("sensitivity_twin_max_pose_rad", json()));  // absent: files before the twin
    r.sensitivity_failed_at = optionalFrom(j.value("sensitivity_twin_failed_at_s", json()));
    if (const json g = j.value("grid_cut_steps", json()); !g.is_null()) r.grid_cut_steps = g.get<long>();  // absent: older files, other schemes
    r.repeats_identical = j.at("repeats_identical").get<bool>();
    r.momentum_p = optionalFrom(j.value("momentum_drift_p", json()));  // absent in files written before the engine study
    r.momentum_H = optionalFrom(j.value("momentum_drift_H", json()));
    r.joint_separation = optionalFrom(j.value("max_joint_separation_m", json()));
    r.formulation = j.value("formulation", std::string());
    r.tuning = j.value("tuning", std::string());  // the keys below are absent in files written before the benchmark
    r.loop_position_m = optionalFrom(j.value("loops_max_position_m", json()));
    r.loop_position_rad = optionalFrom(j.value("loops_max_position_rad", json()));
    r.loop_velocity_m = optionalFrom(j.value("loops_max_velocity_m_per_s", json()));
    r.loop_velocity_rad = optionalFrom(j.value("loops_max_velocity_rad_per_s", json()));
    r.benchmark_error = optionalFrom(j.value("benchmark_error_m", json()));
    r.benchmark_error_t = optionalFrom(j.value("benchmark_error_t_s", json()));
    r.t0 = optionalFrom(j.value("t0_s", json()));
    r.pose_by_t0 = optionalFrom(j.value("pose_error_by_t0_rad", json()));
    r.lyapunov_per_s = optionalFrom(j.value("lyapunov_per_s", json()));
    r.lyapunov_uncertainty_per_s = optionalFrom(j.value("lyapunov_uncertainty_per_s", json()));
    if (j.contains("eigen") && !j["eigen"].is_null()) r.eigen = eigenStatsFrom(j["eigen"]);  // absent in files of d178fb4
  } catch (const std::exception& e) {
    throw std::runtime_error(source + ": not a case result this version wrote (" + e.what() + ")");
  }
  return r;
}

std::vector<CaseRecord> collectRecords(const Plan& plan, const std::string& dir, std::vector<std::string>& missing) {
  std::vector<CaseRecord> out;
  for (const SweepCase& c : planCases(plan)) {
    const std::string path = caseFile(dir, c);
    if (!fs::exists(path)) {
      missing.push_back(c.name);
      continue;
    }
    if (!caseDone(plan, c, dir)) throw std::logic_error("case file vanished: " + path);
    out.push_back(readCaseRecord(parseJsonStrict(readFile(path, "case result")).at("result"), path));
  }
  return out;
}

std::string mergedCsv(const std::vector<CaseRecord>& records, bool with_member) {
  std::ostringstream o;
  o.precision(17);
  o << (with_member ? "scene,member," : "scene,") << "nu,role,method,integrator,setting_kind,setting,status,failure_kind,failure_time_s,max_pose_error_rad,"
       "max_coord_error_rad,energy_error_max,";
  for (const char* what : {"pose", "coord"})
    for (size_t i = 0; i < kCaseThresholds.size(); ++i) o << beyondKey(what, i) << ',';
  o << "steps,rhs_evals,repeats_identical,"
       "momentum_drift_p,momentum_drift_H,max_joint_separation_m,min_gap,max_abs_Omega,jacobi_sweeps,block_merges,block_splits,formulation,tuning,loops_max_position_m,loops_max_position_rad,benchmark_error_m,cpu_median_s,cpu_min_s,cpu_max_s,cpu_per_rhs_s,cpu_per_step_s\n";
  auto opt = [](const std::optional<double>& x) { return x ? gnum(*x, 17) : std::string(); };
  auto num = [](double x) { return std::isfinite(x) ? gnum(x, 17) : std::string(); };
  for (const CaseRecord& r : records) {
    o << r.scene << ',';
    if (with_member) o << r.member << ',';
    o << r.nu << ',' << caseRoleName(r.role) << ',' << r.method << ',' << r.integrator << ',' << settingKindName(r.setting_kind) << ','
      << gnum(r.setting, 17) << ',' << outcomeName(r.status) << ',' << failureName(r.failure_kind) << ',' << opt(r.failure_time) << ','
      << num(r.has_error ? r.max_pose : NAN) << ',' << num(r.has_error ? r.max_coord : NAN) << ',' << num(r.max_energy)
      << ',';
    for (const FirstTimes* times : {&r.pose_beyond, &r.coord_beyond})
      for (const std::optional<double>& t : *times) o << opt(t) << ',';
    o << r.steps << ',' << r.rhs_evals << ','
      << (r.repeats_identical ? "true" : "false") << ',' << opt(r.momentum_p) << ',' << opt(r.momentum_H) << ','
      << opt(r.joint_separation) << ',' << eigenCells(r.eigen) << ',' << r.formulation << ',' << r.tuning << ',' << opt(r.loop_position_m) << ','
      << opt(r.loop_position_rad) << ',' << opt(r.benchmark_error) << ',' << num(r.cpuMedian()) << ',' << num(r.cpuMin()) << ','
      << num(r.cpuMax()) << ',' << num(r.rhs_evals ? r.cpuMedian() / r.rhs_evals : NAN) << ','
      << num(r.steps ? r.cpuMedian() / r.steps : NAN) << '\n';
  }
  return o.str();
}

std::optional<double> timeToReach(const std::vector<double>& cpu, const std::vector<double>& err, double target,
                                  bool& at_first) {
  at_first = false;
  for (size_t k = 0; k < err.size(); ++k) {
    if (!(err[k] <= target)) continue;
    if (k == 0) {
      at_first = true;
      return cpu[0];
    }
    const double e0 = err[k - 1], e1 = err[k];
    if (!(std::isfinite(e0) && e0 > target && e1 > 0 && cpu[k - 1] > 0 && cpu[k] > 0)) return cpu[k];
    const double w = std::log(e0 / target) / std::log(e0 / e1);
    return std::exp(std::log(cpu[k - 1]) + w * (std::log(cpu[k]) - std::log(cpu[k - 1])));
  }
  return std::nullopt;
}

std::optional<double> logSlope(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() < 2 || x.size() != y.size()) return std::nullopt;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (size_t k = 0; k < x.size(); ++k) {
    const double lx = std::log(x[k]), ly = std::log(y[k]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  const double d = n * sxx - sx * sx;
  if (!(std::fabs(d) > 0)) return std::nullopt;
  return (n * sxy - sx * sy) / d;
}

std::string writeMerged(const Plan& plan, const std::string& dir, const std::vector<CaseRecord>& records,
                        const std::vector<std::string>& missing, const Interleaved* timed) {
  const std::string csv = mergedCsv(records, plan.ensemble.has_value());
  std::string md = sweepTables(plan, records, missing, timed);
  writeAtomic((fs::path(dir) / (plan.name + ".csv")).string(), "merged CSV", [&](std::ostream& o) { o << csv; });
  if (plan.ensemble) {
    const std::vector<EnsembleRow> rows = ensembleRows(records);
    md += ensembleTable(rows);
    const std::string ens = ensembleCsv(rows);
    writeAtomic((fs::path(dir) / (plan.name + "-ensemble.csv")).string(), "ensemble CSV", [&](std::ostream& o) { o << ens; });
    const std::vector<Prediction> predicted = predictions(records);
    md += predictionTable(predicted);
    const std::string pred = predictionCsv(predicted);
    writeAtomic((fs::path(dir) / (plan.name + "-prediction.csv")).string(), "prediction CSV", [&](std::ostream& o) { o << pred; });
  }
  writeAtomic((fs::path(dir) / (plan.name + ".md")).string(), "tables", [&](std::ostream& o) { o << md; });
  return md;
}

}  // namespace em
