// The benchmark's tables (docs/benchmark.md, docs/sweep.md "benchmark"): on a
// scene that is a benchmark problem, every route's (method x formulation x
// scheme) cheapest run within each of the problem's precision levels, by its
// own error measure against the reference (compare/benchmark.hpp), with the
// constraint violation and energy error of that run; why a route never got
// there; each owner's fastest route and whether eigenmass's is the cheapest.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "solver/text.hpp"
#include "sweep/sweep.hpp"

namespace em {

namespace {

std::string sci(double x) { return sciCell(x); }

// The benchmark's owners: an engine, eigenmass's formulations and methods,
// and IDA apart (benchmarkOwner).
std::string ownerOf(const CaseRecord& r) { return benchmarkOwner(r.method, r.integrator); }

bool reached(const CaseRecord& r, double level) {
  return r.status == Outcome::Ok && r.benchmark_error && std::isfinite(*r.benchmark_error) && *r.benchmark_error <= level;
}

// A route: one method (and formulation) under one scheme, its runs coarse to fine.
struct BRoute {
  std::string owner, method, formulation, integrator, tuning;
  std::vector<const CaseRecord*> runs;
  std::string name() const {
    return method + (formulation.empty() ? "" : " " + formulation) + " " + integrator + (tuning.empty() ? "" : " [" + tuning + "]");
  }
  // The first run finer than runs[i] that did not complete within `level`, or nullptr:
  // a route whose error leaves the level as its setting tightens does not converge
  // there, and its coarser run's "within" is an accident of the setting (issue 76,
  // item 5: A02's projection under rk8pd, 2.3e-7 m at tol 1e-4, 2.7e-3 m at 1e-10).
  const CaseRecord* breaksAfter(size_t i, double level) const {
    for (size_t j = i + 1; j < runs.size(); ++j)
      if (!reached(*runs[j], level)) return runs[j];
    return nullptr;
  }
  // The cheapest run within `level` whose finer runs all stay within it.
  const CaseRecord* cheapest(double level) const {
    const CaseRecord* best = nullptr;
    for (size_t i = 0; i < runs.size(); ++i)
      if (reached(*runs[i], level) && !breaksAfter(i, level) && (!best || runs[i]->cpuMedian() < best->cpuMedian())) best = runs[i];
    return best;
  }
};

std::vector<BRoute> routesOf(const std::vector<CaseRecord>& rs, const std::string& scene) {
  std::vector<BRoute> out;
  for (const CaseRecord& r : rs) {
    if (r.scene != scene || r.role != CaseRole::Run) continue;
    auto it = std::find_if(out.begin(), out.end(), [&](const BRoute& x) {
      return x.method == r.method && x.formulation == r.formulation && x.integrator == r.integrator && x.tuning == r.tuning;
    });
    if (it == out.end()) it = out.insert(out.end(), BRoute{ownerOf(r), r.method, r.formulation, r.integrator, r.tuning, {}});
    it->runs.push_back(&r);
  }
  for (BRoute& x : out)
    std::stable_sort(x.runs.begin(), x.runs.end(), [](const CaseRecord* a, const CaseRecord* b) { return a->setting > b->setting; });
  return out;
}

std::string settingText(const CaseRecord& r) { return (r.setting_kind == SettingKind::Dt ? "dt " : "tol ") + gnum(r.setting); }

// The run's constraint violation (m): its loops' largest |g| (points), or a maximal-coordinate engine's joint separation.
std::optional<double> violation(const CaseRecord& r) {
  if (r.loop_position_m && r.joint_separation) return std::max(*r.loop_position_m, *r.joint_separation);
  return r.loop_position_m ? r.loop_position_m : r.joint_separation;
}

// Why a route reached no run within `level`: its finer runs left the level, its best error, or how its runs ended.
std::string whyNot(const BRoute& x, double level) {
  for (size_t i = 0; i < x.runs.size(); ++i)
    if (reached(*x.runs[i], level))
      if (const CaseRecord* b = x.breaksAfter(i, level)) {
        const std::string then = b->status == Outcome::Ok && b->benchmark_error ? sci(*b->benchmark_error) + " m"
                                 : std::string(failureName(b->failure_kind)) + " at " + gnum(b->failure_time.value_or(0), 4) + " s";
        return "not converging: " + sci(*x.runs[i]->benchmark_error) + " m at " + settingText(*x.runs[i]) + ", " + then + " at " +
               settingText(*b);
      }
  const CaseRecord* best = nullptr;
  for (const CaseRecord* r : x.runs)
    if (r->status == Outcome::Ok && r->benchmark_error && (!best || *r->benchmark_error < *best->benchmark_error)) best = r;
  if (best) return "not reached: best " + sci(*best->benchmark_error) + " m (" + settingText(*best) + ")";
  const CaseRecord* f = x.runs.empty() ? nullptr : x.runs.back();  // the finest run's failure
  return f ? "not reached: every run failed (finest: " + std::string(failureName(f->failure_kind)) + " at " + gnum(f->failure_time.value_or(0), 4) + " s)"
           : "not reached: no run";
}

// Why a level cannot be judged on this scene ("" when it can): measured against the reference
// run (the problem states no solution), the reference's check failed before the horizon
// (beyond it the reference is unchecked), or it lies within ten times the level.
std::string unresolved(const std::vector<CaseRecord>& rs, const std::string& scene, const BenchmarkSpec& spec, double level) {
  if (spec.hasSolution()) return "";  // judged against the problem's own solution, not our reference
  const auto c = std::find_if(rs.begin(), rs.end(), [&](const CaseRecord& r) { return r.scene == scene && r.role == CaseRole::Check; });
  if (c == rs.end()) return "";
  if (c->status != Outcome::Ok) return "the reference's check failed at " + gnum(c->failure_time.value_or(0), 4) + " s";
  if (c->benchmark_error && *c->benchmark_error > level / 10) return "the reference's check is " + sci(*c->benchmark_error) + " m from it";
  return "";
}

std::string cheapestCell(const CaseRecord& r, double t_end) {
  const std::optional<double> g = violation(r);
  return settingText(r) + " | " + sci(r.cpuMedian()) + " | " + sci(cpuPerSimulatedSecond(r, t_end)) + " | " +
         (g ? sci(*g) : std::string("-")) + " | " + sci(r.max_energy);
}

std::string routeTable(const std::vector<BRoute>& routes, const BenchmarkSpec& spec, double t_end) {
  std::ostringstream o;
  o << "| owner | route | ok / runs |";
  for (double level : spec.levels) o << " within " << gnum(level) << " m | CPU s | CPU s / s | violation (m) | dE / E_scale |";
  o << "\n|---|---|---|";
  for (size_t k = 0; k < spec.levels.size(); ++k) o << "---|---|---|---|---|";
  o << "\n";
  for (const BRoute& x : routes) {
    int ok = 0;
    for (const CaseRecord* r : x.runs) ok += r->status == Outcome::Ok;
    o << "| " << x.owner << " | " << x.name() << " | " << ok << " / " << x.runs.size() << " |";
    for (double level : spec.levels) {
      const CaseRecord* r = x.cheapest(level);
      o << " " << (r ? cheapestCell(*r, t_end) : whyNot(x, level) + " | - | - | - | -") << " |";
    }
    o << "\n";
  }
  return o.str() + "\n";
}

// One owner's fastest route to each level.
struct OwnerBest {
  std::string owner;
  std::vector<const BRoute*> route;
  std::vector<const CaseRecord*> run;
};

std::vector<OwnerBest> fastestByOwner(const std::vector<BRoute>& routes, const BenchmarkSpec& spec) {
  const size_t levels_n = spec.levels.size();
  std::vector<OwnerBest> out;
  for (const BRoute& x : routes) {
    auto it = std::find_if(out.begin(), out.end(), [&](const OwnerBest& b) { return b.owner == x.owner; });
    if (it == out.end())
      it = out.insert(out.end(), OwnerBest{x.owner, std::vector<const BRoute*>(levels_n), std::vector<const CaseRecord*>(levels_n)});
    for (size_t k = 0; k < levels_n; ++k)
      if (const CaseRecord* r = x.cheapest(spec.levels[k]); r && (!it->run[k] || r->cpuMedian() < it->run[k]->cpuMedian()))
        it->route[k] = &x, it->run[k] = r;
  }
  return out;
}

// Whether eigenmass's fastest route beats every other owner's, per level; by how much where it does not.
std::string goalLines(const std::vector<OwnerBest>& owners, const BenchmarkSpec& spec, const std::vector<CaseRecord>& rs,
                      const std::string& scene) {
  std::ostringstream o;
  const auto self = std::find_if(owners.begin(), owners.end(), [](const OwnerBest& b) { return b.owner == kInHouseOwner; });
  if (self == owners.end()) return "";
  for (size_t k = 0; k < spec.levels.size(); ++k) {
    if (const std::string why = unresolved(rs, scene, spec, spec.levels[k]); !why.empty()) {
      o << "- Within " << gnum(spec.levels[k]) << " m: not judged: " << why << ".\n";
      continue;
    }
    const CaseRecord* mine = self->run[k];
    std::vector<std::string> cheaper, dearer;
    for (const OwnerBest& b : owners) {
      if (b.owner == kInHouseOwner || !b.run[k]) continue;
      if (!mine || b.run[k]->cpuMedian() < mine->cpuMedian())
        cheaper.push_back(b.owner + (mine ? " (eigenmass " + gnum(mine->cpuMedian() / b.run[k]->cpuMedian(), 3) + "x its CPU)" : ""));
      else
        dearer.push_back(b.owner + " " + gnum(b.run[k]->cpuMedian() / mine->cpuMedian(), 3) + "x");
    }
    o << "- Within " << gnum(spec.levels[k]) << " m: eigenmass's fastest route is "
      << (!mine ? "none (no route reached it)"
                : self->route[k]->name() + " " + settingText(*mine) + ", " + sci(mine->cpuMedian()) + " CPU s; " +
                      (cheaper.empty() ? "cheaper than every other owner's fastest (" + (dearer.empty() ? std::string("no other reached it") : joined(dearer)) + "): goal met"
                                       : "beaten by " + joined(cheaper) + ": goal missed"))
      << ".\n";
  }
  return o.str() + "\n";
}

std::string runTable(const std::vector<BRoute>& routes, double t_end) {
  std::ostringstream o;
  o << "| route | setting | status | benchmark error (m) | at (s) | violation (m) | dE / E_scale | CPU s | CPU s / s |\n"
    << "|---|---|---|---|---|---|---|---|---|\n";
  for (const BRoute& x : routes)
    for (const CaseRecord* r : x.runs) {
      const std::optional<double> g = violation(*r);
      o << "| " << x.name() << " | " << settingText(*r) << " | "
        << (r->status == Outcome::Ok ? std::string("ok") : std::string(failureName(r->failure_kind)) + " at " + gnum(r->failure_time.value_or(0), 4) + " s") << " | "
        << sci(r->benchmark_error.value_or(NAN)) << " | " << (r->benchmark_error_t ? gnum(*r->benchmark_error_t, 4) : "-") << " | "
        << (g ? sci(*g) : "-") << " | " << sci(r->max_energy) << " | " << sci(r->cpuMedian()) << " | "
        << sci(cpuPerSimulatedSecond(*r, t_end)) << " |\n";
    }
  return o.str() + "\n";
}

// Per level: eigenmass's fastest run and the other owners' fastest runs, cheapest (by their medians) first.
struct LevelCell : Contest {
  const BRoute* mine_route = nullptr;
};

LevelCell levelCell(const std::vector<OwnerBest>& best, size_t k) {
  LevelCell cell;
  for (const OwnerBest& b : best) {
    if (!b.run[k]) continue;
    if (b.owner == kInHouseOwner) cell.mine = b.run[k], cell.mine_route = b.route[k];
    else cell.others.emplace_back(b.owner, b.run[k]);
  }
  std::stable_sort(cell.others.begin(), cell.others.end(),
                   [](const auto& a, const auto& b) { return a.second->cpuMedian() < b.second->cpuMedian(); });
  return cell;
}

}  // namespace

std::vector<std::string> benchmarkContenders(const std::vector<CaseRecord>& rs, const std::string& scene, const BenchmarkSpec& spec) {
  const std::vector<BRoute> routes = routesOf(rs, scene);
  const std::vector<OwnerBest> best = fastestByOwner(routes, spec);
  std::vector<std::string> out;
  for (size_t k = 0; k < spec.levels.size(); ++k) addContenders(levelCell(best, k), out);
  return out;
}

std::string benchmarkScene(const std::vector<CaseRecord>& rs, const std::string& scene, const BenchmarkSpec& spec, double t_end,
                           bool judge) {
  const std::vector<BRoute> routes = routesOf(rs, scene);
  std::ostringstream o;
  std::vector<std::string> measured;
  for (const BenchmarkPoint& p : spec.measure) measured.push_back(p.name);
  const double step = spec.outputStep();
  const long steps = std::lround(std::min(t_end, spec.t_end) / step);
  o << "Problem " << spec.problem << ": error measure " << joined(measured) << " (m) at " << steps << " output steps of "
    << gnum(step) << " s" << (t_end < spec.t_end * (1 - 1e-12) ? " (the problem's " + std::to_string(spec.outputs) + " cut to this run's horizon " + gnum(t_end) + " s)" : "")
    << (spec.hasSolution() ? ", against the problem's solution (the scene's benchmark.solution)" : ", against the reference")
    << "; precision levels ";
  std::vector<std::string> levels;
  for (double l : spec.levels) levels.push_back(gnum(l) + " m");
  o << joined(levels) << ".";
  const auto check = std::find_if(rs.begin(), rs.end(), [&](const CaseRecord& r) { return r.scene == scene && r.role == CaseRole::Check; });
  if (spec.hasSolution()) {  // the reference and its check measured like every run
    for (const CaseRole role : {CaseRole::Reference, CaseRole::Check}) {
      const auto c = std::find_if(rs.begin(), rs.end(), [&](const CaseRecord& r) { return r.scene == scene && r.role == role; });
      if (c == rs.end() || !c->benchmark_error) continue;
      o << " The " << (role == CaseRole::Check ? "reference's check" : "reference run") << " is " << sci(*c->benchmark_error)
        << " m from the solution"
        << (c->status != Outcome::Ok ? " up to " + gnum(c->failure_time.value_or(0), 4) + " s, where it failed (" + failureName(c->failure_kind) + ")" : "") << ".";
    }
  } else if (check != rs.end() && check->benchmark_error) {
    o << " The reference's check is " << sci(*check->benchmark_error) << " m from it by this measure";
    if (check->status != Outcome::Ok)
      o << " up to " << gnum(check->failure_time.value_or(0), 4) << " s, where the check failed (" << failureName(check->failure_kind)
        << "): beyond it the reference stands unchecked";
    for (double l : spec.levels)
      if (*check->benchmark_error > l / 10) o << "; the level " << gnum(l) << " m is within ten times that: not resolved";
    o << ".";
  }
  o << "\n\n";
  o << "#### Each route's cheapest run within each level\n\n"
    << "A run counts within a level only when every finer run of its route also completed within it; a route "
       "whose error leaves the level as its setting tightens is marked not converging, with both runs.\n\n"
    << routeTable(routes, spec, t_end);
  const std::vector<OwnerBest> owners = fastestByOwner(routes, spec);
  o << "#### Each owner's fastest route\n\n| owner |";
  for (double l : spec.levels) o << " within " << gnum(l) << " m | CPU s |";
  o << "\n|---|";
  for (size_t k = 0; k < spec.levels.size(); ++k) o << "---|---|";
  o << "\n";
  for (const OwnerBest& b : owners) {
    o << "| " << b.owner << " |";
    for (size_t k = 0; k < spec.levels.size(); ++k)
      o << " " << (b.run[k] ? b.route[k]->name() + " " + settingText(*b.run[k]) + " | " + sci(b.run[k]->cpuMedian()) : std::string("not reached | -")) << " |";
    o << "\n";
  }
  o << "\n" << (judge ? goalLines(owners, spec, rs, scene) : "- Goals not judged: the results are incomplete (above).\n\n");
  o << "#### Every run\n\n" << runTable(routes, t_end);
  return o.str();
}

std::string benchmarkSummary(const std::vector<BenchmarkProblem>& problems) {
  std::vector<std::string> owners;  // in order of first appearance, eigenmass first
  owners.push_back(kInHouseOwner);
  for (const BenchmarkProblem& p : problems)
    for (const CaseRecord& r : p.records)
      if (r.role == CaseRole::Run && std::find(owners.begin(), owners.end(), ownerOf(r)) == owners.end()) owners.push_back(ownerOf(r));
  std::ostringstream o;
  o << "CPU s of each owner's fastest route within each precision level (its whole run, the horizon's, median of "
       "its repeats; - : no route reached it); eigenmass's route; whether it is the cheapest. The verdict's ratio is the "
       "median over "
    << kInterleavedRounds << " interleaved rounds (each runs eigenmass's route and the " << kContendersPerLevel
    << " cheapest other owners' once, in turn) of other / eigenmass, with its 10th-90th percentile interval; an owner more "
       "than " << gnum(kRetimeWithin) << " times dearer by the medians is not timed again, its interval the extremes of the "
       "consecutive repeats. Met where every such interval lies above 1, tied where one holds 1, missed where one lies below.\n\n| problem | level (m) |";
  for (const std::string& w : owners) o << " " << w << " |";
  o << " eigenmass's route | goal |\n|---|---|";
  for (size_t k = 0; k < owners.size(); ++k) o << "---|";
  o << "---|---|\n";
  for (const BenchmarkProblem& p : problems) {
    const std::vector<BRoute> routes = routesOf(p.records, p.scene);
    const std::vector<OwnerBest> best = fastestByOwner(routes, p.spec);
    for (size_t k = 0; k < p.spec.levels.size(); ++k) {
      o << "| " << p.spec.problem << " | " << gnum(p.spec.levels[k]) << " |";
      for (const std::string& w : owners) {
        const auto it = std::find_if(best.begin(), best.end(), [&](const OwnerBest& b) { return b.owner == w; });
        const CaseRecord* r = it == best.end() ? nullptr : it->run[k];
        o << " " << (r ? sci(r->cpuMedian()) : std::string("-")) << " |";
      }
      const LevelCell cell = levelCell(best, k);
      // A winner at its route's finest setting has no finer run to show that it converges (issue 76, item 5): said.
      const bool finest = cell.mine && cell.mine == cell.mine_route->runs.back();
      o << " " << (cell.mine ? cell.mine_route->name() + " " + settingText(*cell.mine) + (finest ? " (its finest: convergence unchecked)" : "")
                             : std::string("-"))
        << " | ";
      const std::string why = unresolved(p.records, p.scene, p.spec, p.spec.levels[k]);
      if (!p.complete) o << "not judged (incomplete)";
      else if (!why.empty()) o << "not judged: " << why;
      else if (!cell.mine) o << "missed: not reached";
      else o << marginVerdict(cell, p.interleaved);
      o << " |\n";
    }
  }
  return o.str() + "\n";
}

}  // namespace em
