// The Markdown tables of a sweep's merged results (docs/sweep.md, "Tables"):
// the reference and its check, work-precision (time to reach an error, the
// observed order) and cost against size (fitted exponents).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "sweep/sweep.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

// The headings name the case thresholds as "1e-3 rad" and "0.1 rad" (pose_beyond[0], [1]).
static_assert(kCaseThresholds[0] == 1e-3 && kCaseThresholds[1] == 1e-1, "the tables' headings name these thresholds");

const CaseRecord* findRole(const std::vector<CaseRecord>& rs, const std::string& scene, CaseRole role) {
  for (const CaseRecord& r : rs)
    if (r.scene == scene && r.role == role) return &r;
  return nullptr;
}

std::vector<std::string> scenesOf(const std::vector<CaseRecord>& rs) {
  std::vector<std::string> out;
  for (const CaseRecord& r : rs)
    if (std::find(out.begin(), out.end(), r.scene) == out.end()) out.push_back(r.scene);
  return out;
}

// A route's name in the tables: the method, and its formulation where the case names one (issue 73,
// item 4: three formulations under one method were pooled into one row, their order fitted across all).
// A line's tuning set is a route of its own (issue 76: every owner at its settings).
std::string routeName(const CaseRecord& r) {
  return r.method + (r.formulation.empty() ? "" : " " + r.formulation) + (r.tuning.empty() ? "" : " [" + r.tuning + "]");
}

// A line of a diagram: the runs of one route (method and formulation) under one integrator on one scene, coarse to fine.
struct Line {
  std::string method, integrator;  // method: routeName
  std::vector<const CaseRecord*> points;
  bool fixed() const { return !points.empty() && points[0]->setting_kind == SettingKind::Dt; }
};

std::vector<Line> linesOf(const std::vector<CaseRecord>& rs, const std::string& scene) {
  std::vector<Line> out;
  for (const CaseRecord& r : rs) {
    if (r.scene != scene || r.role != CaseRole::Run) continue;
    auto it = std::find_if(out.begin(), out.end(), [&](const Line& l) { return l.method == routeName(r) && l.integrator == r.integrator; });
    if (it == out.end()) it = out.insert(out.end(), Line{routeName(r), r.integrator, {}});
    it->points.push_back(&r);
  }
  for (Line& l : out)
    std::stable_sort(l.points.begin(), l.points.end(), [](const CaseRecord* a, const CaseRecord* b) { return a->setting > b->setting; });
  return out;
}

std::string sci(double x, int digits = 2) { return sciCell(x, digits); }

std::string referenceLine(const std::vector<CaseRecord>& rs, const std::string& scene, double& floor) {
  std::ostringstream o;
  floor = 0;
  const CaseRecord* ref = findRole(rs, scene, CaseRole::Reference);
  if (!ref) return "";
  o << "Reference: " << ref->method << " " << ref->integrator << " " << settingKindName(ref->setting_kind) << " " << gnum(ref->setting) << ", "
    << outcomeName(ref->status) << (ref->status == Outcome::Ok ? "" : " (" + ref->failure + ")") << ", " << ref->steps << " steps.";
  if (const CaseRecord* chk = findRole(rs, scene, CaseRole::Check)) {
    floor = std::max(chk->max_pose, std::isfinite(chk->max_coord) ? chk->max_coord : 0.0);
    o << " Its check, " << chk->method << " " << chk->integrator << " " << settingKindName(chk->setting_kind) << " " << gnum(chk->setting)
      << ": max pose difference " << sci(chk->max_pose) << " rad, max coordinate difference " << sci(chk->max_coord)
      << " rad: the floor of every error below.";
    const FirstTimes& part = chk->pose_beyond;
    if (part[0] || part[1])
      o << " They part by 1e-3 rad at " << (part[0] ? gnum(*part[0], 4) + " s" : "no time")
        << " and by 0.1 rad at " << (part[1] ? gnum(*part[1], 4) + " s" : "no time")
        << ": the reference horizon (chaos); a divergence after it says nothing about a method.";
  }
  return o.str() + "\n\n";
}

// Slope of log error against log dt over the ok points above 10x the floor and below 0.1 rad.
std::string observedOrder(const Line& l, double floor, bool coord) {
  if (!l.fixed()) return "";
  std::vector<double> dt, err;
  for (const CaseRecord* p : l.points) {
    const double e = coord ? p->max_coord : p->max_pose;
    if (p->status == Outcome::Ok && std::isfinite(e) && e > 10 * floor && e < 0.1) dt.push_back(p->setting), err.push_back(e);
  }
  const std::optional<double> s = logSlope(dt, err);
  return s ? gnum(*s, 3) + " (" + std::to_string(dt.size()) + " pts)" : "-";
}

std::string reachCell(const Line& l, double target) {
  std::vector<double> cpu, err;
  for (const CaseRecord* p : l.points) {
    cpu.push_back(p->cpuMedian());
    err.push_back(p->status == Outcome::Ok ? p->max_pose : INFINITY);
  }
  bool at_first = false;
  const std::optional<double> t = timeToReach(cpu, err, target, at_first);
  if (!t) return "not reached";
  return (at_first ? "≤ " : "") + sci(*t) + " s";
}

std::string workPrecisionTable(const std::vector<CaseRecord>& rs, const std::string& scene) {
  std::ostringstream o;
  double floor = 0;
  o << "### " << scene << "\n\n" << referenceLine(rs, scene, floor);
  o << "| method | integrator | ok / runs | smallest pose error (rad) | CPU to 1e-3 rad | CPU to 1e-6 rad | order (coord) | order (pose) |\n"
    << "|---|---|---|---|---|---|---|---|\n";
  for (const Line& l : linesOf(rs, scene)) {
    int ok = 0;
    double best = INFINITY;
    for (const CaseRecord* p : l.points)
      if (p->status == Outcome::Ok) ++ok, best = std::min(best, p->max_pose);
    o << "| " << l.method << " | " << l.integrator << " | " << ok << " / " << l.points.size() << " | " << sci(best) << " | "
      << reachCell(l, 1e-3) << " | " << reachCell(l, 1e-6) << " | " << observedOrder(l, floor, true) << " | "
      << observedOrder(l, floor, false) << " |\n";
  }
  return o.str() + "\n";
}

// Cost against size: one column per method x integrator x setting, one row per scene (by size).
struct CostColumn {
  std::string label;
  std::map<std::string, const CaseRecord*> by_scene;
};

std::vector<CostColumn> costColumns(const std::vector<CaseRecord>& rs) {
  std::vector<CostColumn> out;
  for (const CaseRecord& r : rs) {
    if (r.role != CaseRole::Run) continue;
    const std::string label = routeName(r) + " " + r.integrator + " " + gnum(r.setting);
    auto it = std::find_if(out.begin(), out.end(), [&](const CostColumn& c) { return c.label == label; });
    if (it == out.end()) it = out.insert(out.end(), CostColumn{label, {}});
    it->by_scene[r.scene] = &r;
  }
  return out;
}

using CostValue = double (*)(const CaseRecord&, double t_end);

std::string costTable(const std::vector<CaseRecord>& rs, double t_end, const char* title, CostValue value, double unit) {
  std::vector<std::pair<int, std::string>> scenes;
  for (const std::string& s : scenesOf(rs))
    for (const CaseRecord& r : rs)
      if (r.scene == s) {
        scenes.push_back({r.nu, s});
        break;
      }
  std::stable_sort(scenes.begin(), scenes.end());
  const std::vector<CostColumn> cols = costColumns(rs);
  std::ostringstream o;
  o << "#### " << title << "\n\n| scene | n |";
  for (const CostColumn& c : cols) o << " " << c.label << " |";
  o << "\n|---|---|";
  for (size_t k = 0; k < cols.size(); ++k) o << "---|";
  o << "\n";
  for (const auto& [n, s] : scenes) {
    o << "| " << s << " | " << n << " |";
    for (const CostColumn& c : cols) {
      auto it = c.by_scene.find(s);
      o << " " << (it == c.by_scene.end() ? "" : gnum(value(*it->second, t_end) / unit, 3) + (it->second->status == Outcome::Ok ? "" : "†")) << " |";
    }
    o << "\n";
  }
  o << "| exponent | upper half of n |";
  const size_t from = scenes.size() / 2;
  for (const CostColumn& c : cols) {
    std::vector<double> n, v;
    for (size_t k = from; k < scenes.size(); ++k) {
      auto it = c.by_scene.find(scenes[k].second);
      if (it != c.by_scene.end()) n.push_back(scenes[k].first), v.push_back(value(*it->second, t_end));
    }
    const std::optional<double> e = logSlope(n, v);
    o << " " << (e ? gnum(*e, 3) : "-") << " |";
  }
  return o.str() + "\n\n";
}

double perRhs(const CaseRecord& r, double) { return r.rhs_evals ? r.cpuMedian() / r.rhs_evals : NAN; }
double perStep(const CaseRecord& r, double) { return r.steps ? r.cpuMedian() / r.steps : NAN; }
double perSecond(const CaseRecord& r, double t_end) { return cpuPerSimulatedSecond(r, t_end); }

// Every run: outcome, divergence times, energy, cost and the eigenfactor
// diagnostics (plans with the runs or trajectories table).
std::string runsTable(const std::vector<CaseRecord>& rs) {
  std::ostringstream o;
  o << "| scene | method | integrator | setting | status | pose > 1e-3 rad (s) | pose > 0.1 rad (s) | joint > 0.1 rad (s) | "
       "max pose err (rad) | max dE/Escl | µs / step | min gap | max abs(Omega) | merges / splits |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  auto when = [](const std::optional<double>& t) { return t ? gnum(*t, 4) : std::string("-"); };
  for (const CaseRecord& r : rs) {
    if (r.role != CaseRole::Run) continue;
    o << "| " << r.scene << " | " << routeName(r) << " | " << r.integrator << " | " << gnum(r.setting) << " | "
      << (r.status == Outcome::Ok ? std::string(outcomeName(r.status)) : std::string(failureName(r.failure_kind)) + " at " + gnum(r.failure_time.value_or(0), 4) + " s") << " | "
      << when(r.pose_beyond[0]) << " | " << when(r.pose_beyond[1]) << " | " << when(r.coord_beyond[1]) << " | " << sci(r.max_pose) << " | "
      << sci(r.max_energy) << " | " << gnum(r.steps ? r.cpuMedian() / r.steps * 1e6 : NAN, 3) << " | "
      << (r.eigen ? sci(r.eigen->min_gap) + " | " + sci(r.eigen->max_abs_Omega) + " | " +
                        std::to_string(r.eigen->block_merges) + " / " + std::to_string(r.eigen->block_splits)
                  : std::string("| |"))
      << " |\n";
  }
  return o.str() + "\n";
}

}  // namespace

std::string sciCell(double x, int digits) {
  if (!std::isfinite(x)) return "-";
  char b[32];
  std::snprintf(b, sizeof b, "%.*e", digits, x);
  return b;
}

double cpuPerSimulatedSecond(const CaseRecord& r, double t_end) { return r.cpuMedian() / r.failure_time.value_or(t_end); }

std::string sweepTables(const Plan& plan, const std::vector<CaseRecord>& records, const std::vector<std::string>& missing,
                        const Interleaved* timed) {
  std::ostringstream o;
  o << "## " << plan.name << "\n\n" << (plan.description.empty() ? "" : plan.description + "\n\n");
  if (!missing.empty())
    o << "**Incomplete: " << missing.size() << " of " << missing.size() + records.size()
      << " cases have no result in this folder (the first: " << missing[0] << "). The tables cover the " << records.size()
      << " that do; no goal is judged on them.**\n\n";
  o << "Horizon " << gnum(plan.t_end) << " s; CPU times are the median of " << plan.repeats
    << " repeats of the integration alone (min and max in the CSV).\n\n";
  o << leftOutLines(plan);
  if (plan.hasTable(PlanTable::WorkPrecision))
    for (const std::string& s : scenesOf(records)) o << workPrecisionTable(records, s);
  if (plan.hasTable(PlanTable::CostVsSize)) {
    o << "### Cost against size\n\n† the run failed before the horizon (its cost up to the failure).\n\n";
    o << costTable(records, plan.t_end, "µs per right-hand-side evaluation", perRhs, 1e-6);
    o << costTable(records, plan.t_end, "µs per accepted step", perStep, 1e-6);
    o << costTable(records, plan.t_end, "CPU s per simulated second (the paper's Fig. 4 quantity)", perSecond, 1);
  }
  if (plan.hasTable(PlanTable::EngineStudy)) {
    for (const std::string& s : scenesOf(records)) {
      double floor = 0;
      o << "### " << s << "\n\n" << referenceLine(records, s, floor);
      o << engineStudyScene(records, s, plan.t_end, plan.output_dt, floor, missing.empty(), timed);
    }
    o << "### Which engine for what: across the scenes\n\n" << engineStudySummary(records, scenesOf(records), plan.t_end, timed);
  }
  if (plan.hasTable(PlanTable::Benchmark))
    for (const PlanScene& ps : plan.scenes) {
      double floor = 0;
      o << "### " << ps.stem() << "\n\n" << referenceLine(records, ps.stem(), floor);
      o << benchmarkScene(records, ps.stem(), *ps.benchmark, plan.t_end, missing.empty());
    }
  if (!plan.hasTable(PlanTable::WorkPrecision) && !plan.hasTable(PlanTable::EngineStudy) && !plan.hasTable(PlanTable::Benchmark))
    for (const std::string& s : scenesOf(records)) {
      double floor = 0;
      const std::string line = referenceLine(records, s, floor);
      if (!line.empty()) o << "**" << s << "**. " << line;
    }
  if (plan.hasTable(PlanTable::Runs) || plan.hasTable(PlanTable::Trajectories)) o << runsTable(records);
  return o.str();
}

}  // namespace em
