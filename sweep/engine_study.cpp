// The engine study's tables (docs/engines.md, docs/sweep.md "engine-study"):
// for each scene, every route's (method x scheme) cheapest run within 1e-3
// and 1e-6 rad of the reference over the horizon, each owner's fastest route
// beside eigenmass's, and every run's errors, drifts and cost; then, across
// the scenes, which engine was cheapest at which accuracy.
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>

#include "compare/sensitivity.hpp"
#include "solver/registry.hpp"
#include "solver/text.hpp"
#include "sweep/sweep.hpp"

namespace em {

namespace {

// The headings name the case thresholds as "1e-3 rad" and "0.1 rad" (pose_beyond[0], [1]).
static_assert(kCaseThresholds[0] == 1e-3 && kCaseThresholds[1] == 1e-1, "the tables' headings name these thresholds");

constexpr double kAccuracies[] = {1e-3, 1e-6};  // rad: the pose error a route must keep over the horizon

std::string sci(double x) { return sciCell(x); }

std::string when(const std::optional<double>& t) { return t ? gnum(*t, 4) : std::string("-"); }

double perSimulatedSecond(const CaseRecord& r, double t_end) { return cpuPerSimulatedSecond(r, t_end); }

bool within(const CaseRecord& r, double accuracy) {
  return r.status == Outcome::Ok && r.has_error && std::isfinite(r.max_pose) && r.max_pose <= accuracy;
}

// Two runs of an in-house adaptive route that are one run: the same steps,
// evaluations and error, bit for bit. GSL ends a step at the next output
// time, so where the controller's step exceeds the output interval every
// tolerance loose enough takes the grid's steps (Trajectory::grid_cut_steps).
bool sameRun(const CaseRecord& a, const CaseRecord& b) {
  return a.grid_cut_steps && b.grid_cut_steps && a.status == b.status && a.steps == b.steps &&
         a.rhs_evals == b.rhs_evals && a.max_pose == b.max_pose && a.max_energy == b.max_energy;
}

// A route: one method under one scheme on one scene, its runs coarse to fine.
struct Route {
  std::string owner, method, integrator, tuning;
  std::vector<const CaseRecord*> runs;
  std::string label() const { return method + (tuning.empty() ? "" : " [" + tuning + "]"); }
  /// The cheapest run within `accuracy` (CPU per simulated second), if any;
  /// of runs that are one run (sameRun), the loosest setting stands for them,
  /// with its own timing (the others' differ by the machine's noise alone).
  const CaseRecord* cheapest(double accuracy, double t_end) const {
    const CaseRecord* best = nullptr;
    for (const CaseRecord* r : runs)
      if (loosestOf(*r) == r && within(*r, accuracy) && (!best || perSimulatedSecond(*r, t_end) < perSimulatedSecond(*best, t_end)))
        best = r;
    return best;
  }
  /// The loosest run that is one run with `r` (r itself when none is).
  const CaseRecord* loosestOf(const CaseRecord& r) const {
    for (const CaseRecord* x : runs)  // coarse to fine
      if (x == &r || sameRun(*x, r)) return x;
    return &r;
  }
};

std::vector<Route> routesOf(const std::vector<CaseRecord>& rs, const std::string& scene) {
  std::vector<Route> out;
  for (const CaseRecord& r : rs) {
    if (r.scene != scene || r.role != CaseRole::Run || r.member != 0) continue;
    auto it = std::find_if(out.begin(), out.end(), [&](const Route& x) {
      return x.method == r.method && x.integrator == r.integrator && x.tuning == r.tuning;
    });
    if (it == out.end()) it = out.insert(out.end(), Route{routeOwner(r.method), r.method, r.integrator, r.tuning, {}});
    it->runs.push_back(&r);
  }
  for (Route& x : out)
    std::stable_sort(x.runs.begin(), x.runs.end(), [](const CaseRecord* a, const CaseRecord* b) { return a->setting > b->setting; });
  return out;
}

// The engine whose dynamics a route integrates: an engine's own route's
// owner, or the engine an engine's u' under the in-house integrators is of.
std::string dynamicsOwner(const Route& x) {
  Method m;
  return findMethod(x.method, m) && info(m).dynamics_of ? info(m).dynamics_of : x.owner;
}

// The smallest error of a route's runs (ok, measured), or none.
std::optional<double> smallestError(const Route& x) {
  std::optional<double> e;
  for (const CaseRecord* r : x.runs)
    if (r->status == Outcome::Ok && r->has_error && std::isfinite(r->max_pose)) e = std::min(e.value_or(INFINITY), r->max_pose);
  return e;
}

// The error of a route's finest run that completed (runs are coarse to fine),
// or none: its converged error, which an under-resolved run's may understate
// where integration error cancels part of the model's (issue 75: MuJoCo's
// floor on the hand read 2.45e-3 rad from rk4 at dt 5e-4; its converged runs,
// rk4 at 1e-4 and rk8pd at 1e-8 and 1e-10, all give about 9.0e-3).
std::optional<double> finestError(const Route& x) {
  for (auto r = x.runs.rbegin(); r != x.runs.rend(); ++r)
    if ((*r)->status == Outcome::Ok && (*r)->has_error && std::isfinite((*r)->max_pose)) return (*r)->max_pose;
  return std::nullopt;
}

// Above this many times what the in-house methods reach under the same
// integrators, an engine's own u' is held back by its model, not by them.
constexpr double kFloorFactor = 10;

// An engine's floor on this scene: the error of its own u' under the in-house
// integrators (MethodInfo::dynamics_of) at each scheme's finest run, the
// smallest over the schemes: how far
// its dynamics, integrated as well as the study integrates, lie from the exact
// motion (MuJoCo's inertias rounded at compile time). Only where that exceeds
// kFloorFactor times the in-house methods' best under the same schemes: else
// it is those schemes' limit on this scene (a sensitive motion), not the
// engine's. None where its u' was not run (or for eigenmass itself).
std::optional<double> dynamicsFloor(const std::vector<Route>& routes, const std::string& engine) {
  std::optional<double> floor, inhouse;
  std::vector<std::string> schemes;
  for (const Route& x : routes) {
    Method m;
    if (!findMethod(x.method, m) || !info(m).dynamics_of || engine != info(m).dynamics_of) continue;
    if (const std::optional<double> e = finestError(x)) floor = std::min(floor.value_or(INFINITY), *e);
    schemes.push_back(x.integrator);
  }
  for (const Route& x : routes)
    if (x.owner == kInHouseOwner && std::find(schemes.begin(), schemes.end(), x.integrator) != schemes.end())
      if (const std::optional<double> e = smallestError(x)) inhouse = std::min(inhouse.value_or(INFINITY), *e);
  if (!floor || (inhouse && *floor <= kFloorFactor * *inhouse)) return std::nullopt;
  return floor;
}

// Each engine's floor on a scene (dynamicsFloor), measured once, in the routes' order.
using Floors = std::vector<std::pair<std::string, double>>;

// Where accuracies are ill-conditioned (ill[a]), a floor is said only above an
// accuracy that is judged: below it, the scene's amplification of round-off,
// not the engine's model, may set the error (the hand at seed 3, ill at 1e-6
// rad, read DART and Bullet floors of 1.1e-5 rad though their u' are ours).
Floors floorsOf(const std::vector<Route>& routes, const bool ill[2]) {
  Floors out;
  for (const Route& x : routes) {
    const std::string engine = dynamicsOwner(x);
    if (std::any_of(out.begin(), out.end(), [&](const auto& f) { return f.first == engine; })) continue;
    if (const std::optional<double> floor = dynamicsFloor(routes, engine)) {
      bool above_judged = false;
      for (int a = 0; a < 2; ++a) above_judged = above_judged || (!ill[a] && *floor > kAccuracies[a]);
      if (above_judged) out.emplace_back(engine, *floor);
    }
  }
  return out;
}

// A route that never got within `accuracy`: "floor 6.56e-04 rad" where its
// engine's own dynamics do not get there under any integrator, else "not reached".
std::string notReached(const Floors& floors, const Route& x, double accuracy) {
  const std::string engine = dynamicsOwner(x);
  const auto f = std::find_if(floors.begin(), floors.end(), [&](const auto& e) { return e.first == engine; });
  return f != floors.end() && f->second > accuracy ? "floor " + sci(f->second) + " rad" : "not reached";
}

std::string settingText(const CaseRecord& r) { return (r.setting_kind == SettingKind::Dt ? "dt " : "tol ") + gnum(r.setting); }

// Whether each accuracy is ill-conditioned on a scene: the reference's
// sensitivity twin (compare/sensitivity.hpp) parts from it by more.
struct Conditioning {
  bool ill[2] = {false, false};
  std::optional<Sensitivity> twin;
  /// The reference and its check differ by more than a tenth of the accuracy:
  /// a route's error there is the reference's as much as its own, and no verdict
  /// is given (the hand at seed 2: 1.12e-6 rad at 1e-6).
  bool unresolved[2] = {false, false};
  double check_rad = 0;
  bool judged(int a) const { return !ill[a] && !unresolved[a]; }
};

Conditioning conditioningOf(const std::vector<CaseRecord>& rs, const std::string& scene) {
  Conditioning c;
  const auto ref = std::find_if(rs.begin(), rs.end(), [&](const CaseRecord& r) { return r.scene == scene && r.role == CaseRole::Reference; });
  if (ref == rs.end() || !ref->sensitivity_rad) return c;
  const auto chk = std::find_if(rs.begin(), rs.end(), [&](const CaseRecord& r) { return r.scene == scene && r.role == CaseRole::Check; });
  if (chk != rs.end()) {  // the same floor as the reference line's (sweep_tables.cpp)
    c.check_rad = std::max(chk->max_pose, std::isfinite(chk->max_coord) ? chk->max_coord : 0.0);
    for (int a = 0; a < 2; ++a) c.unresolved[a] = c.check_rad > kAccuracies[a] / 10;
  }
  c.twin = Sensitivity{kSensitivitySigma, *ref->sensitivity_rad, ref->sensitivity_failed_at};
  for (int a = 0; a < 2; ++a) c.ill[a] = illConditioned(*c.twin, kAccuracies[a]);
  return c;
}

constexpr const char* kIll = "ill-conditioned | -";

// What the reference's twin measured, at round-off's scale (compare/sensitivity.hpp).
std::string twinText(const Sensitivity& t) {
  const std::string start = "the reference's sensitivity twin, started " + sci(t.sigma) + " away in every coordinate and speed, ";
  if (t.failed_at) return start + "stopped at " + gnum(*t.failed_at, 4) + " s where the reference did not";
  if (t.saturated())
    return start + "parts from it by " + sci(t.max_pose_rad) + " rad, beyond its linear regime (" + sci(kTwinLinearRad) +
           " rad): the amplification of a start's error is at least " + sci(t.amplification()) + " and round-off's reach unknown";
  return start + "parts from it by " + sci(t.max_pose_rad) + " rad: an amplification of " + sci(t.amplification()) +
         ", so round-off (" + sci(kRoundoffScale) + " relative) grows to " + sci(t.roundoffPoseRad()) +
         " rad (an accuracy is ill-conditioned where that exceeds a tenth of it)";
}

// One owner's fastest route to each accuracy.
struct Fastest {
  const Route* route[2] = {nullptr, nullptr};
  const CaseRecord* run[2] = {nullptr, nullptr};
};

std::vector<std::pair<std::string, Fastest>> fastestByOwner(const std::vector<Route>& routes, double t_end) {
  std::vector<std::pair<std::string, Fastest>> out;
  for (const Route& x : routes) {
    auto it = std::find_if(out.begin(), out.end(), [&](const auto& p) { return p.first == x.owner; });
    if (it == out.end()) it = out.insert(out.end(), {x.owner, Fastest{}});
    for (int a = 0; a < 2; ++a)
      if (const CaseRecord* r = x.cheapest(kAccuracies[a], t_end);
          r && (!it->second.run[a] || perSimulatedSecond(*r, t_end) < perSimulatedSecond(*it->second.run[a], t_end)))
        it->second.route[a] = &x, it->second.run[a] = r;
  }
  return out;
}

// Whether an owner is an engine's u' under the in-house integrators (a "-udot" row).
bool hybridOwner(const std::string& owner) {
  Method m;
  return findMethod(owner, m) && info(m).dynamics_of;
}

// eigenmass's fastest run at accuracy a against the other owners' (every
// owner, or the engines' u' under the in-house integrators alone: `hybrid_only`).
Contest contestOf(const std::vector<std::pair<std::string, Fastest>>& by_owner, int a, double t_end, bool hybrid_only) {
  Contest c;
  for (const auto& [owner, f] : by_owner) {
    if (!f.run[a]) continue;
    if (owner == kInHouseOwner) c.mine = f.run[a];
    else if (!hybrid_only || hybridOwner(owner)) c.others.emplace_back(owner, f.run[a]);
  }
  std::stable_sort(c.others.begin(), c.others.end(), [&](const auto& x, const auto& y) {
    return perSimulatedSecond(*x.second, t_end) < perSimulatedSecond(*y.second, t_end);
  });
  return c;
}

std::string routeCell(const Fastest& f, int a, double t_end, const Conditioning& c) {
  if (c.ill[a]) return kIll;
  if (!f.run[a]) return "not reached | -";
  return f.route[a]->label() + " " + f.route[a]->integrator + " " + settingText(*f.run[a]) + " | " +
         sci(perSimulatedSecond(*f.run[a], t_end));
}

// Under the route table: each adaptive route whose tolerances gave one run,
// which tolerances, and that the output grid, not the tolerance, set its steps.
std::string gridBoundLines(const std::vector<Route>& routes, double output_dt) {
  std::ostringstream o;
  for (const Route& x : routes)
    for (size_t i = 0; i < x.runs.size(); ++i) {
      const CaseRecord& first = *x.runs[i];
      size_t j = i;
      while (j + 1 < x.runs.size() && sameRun(*x.runs[j + 1], first)) ++j;
      if (j == i || (i > 0 && sameRun(*x.runs[i - 1], first))) continue;
      o << "- " << x.label() << " " << x.integrator << ": tolerances " << gnum(first.setting) << " to "
        << gnum(x.runs[j]->setting) << " gave one run, step for step (" << first.steps << " steps, "
        << *first.grid_cut_steps << " of them cut short by the " << gnum(output_dt) << "-s output grid): the grid, "
        << "not the tolerance, set its steps, and the table names the loosest.\n";
      i = j;
    }
  const std::string lines = o.str();
  return lines.empty() ? "" : "Tolerances the output grid made meaningless (GSL's steppers end a step at each output time and have no "
                              "dense output to sample by):\n\n" + lines + "\n";
}

// Under the route table, where a floor was said: what it is.
std::string floorLines(const Floors& floors) {
  std::ostringstream o;
  for (const auto& [engine, floor] : floors) {
    if (floor <= kAccuracies[1]) continue;
    o << "- " << engine << ": floor " << sci(floor) << " rad, the error of its own u' under the in-house "
      << "integrators at their finest settings here (the smallest over the schemes). No scheme of it gets below that: the difference is its dynamics' (its model of the scene), "
      << "not its integrator's.\n";
  }
  const std::string lines = o.str();
  return lines.empty() ? "" : "Floors (an engine's model, not its integrator, bounds its accuracy):\n\n" + lines + "\n";
}

bool anyOf(const std::vector<Route>& routes, std::optional<double> CaseRecord::*field) {
  for (const Route& x : routes)
    for (const CaseRecord* r : x.runs)
      if (r->*field) return true;
  return false;
}

// A mechanism's run: how far its loops stood open at its samples, by eigenmass's g(q) (m, rad).
std::string loopsCell(const CaseRecord& r) {
  return r.loop_position_m ? sci(*r.loop_position_m) + ", " + sci(r.loop_position_rad.value_or(0)) : std::string("-");
}

std::string routeTable(const std::vector<Route>& routes, double t_end, const Conditioning& c, const Floors& floors) {
  const bool loops = anyOf(routes, &CaseRecord::loop_position_m);  // a mechanism: the violation of each cheapest run
  const std::string open = loops ? " loops open (m, rad) |" : "";
  std::ostringstream o;
  o << "| owner | method | scheme | ok / runs | cheapest within 1e-3 rad | CPU s / s |" << open
    << " cheapest within 1e-6 rad | CPU s / s |" << open << "\n|---|---|---|---|---|---|---|---|" << (loops ? "---|---|" : "") << "\n";
  for (const Route& x : routes) {
    int ok = 0;
    for (const CaseRecord* r : x.runs) ok += r->status == Outcome::Ok;
    o << "| " << x.owner << " | " << x.label() << " | " << x.integrator << " | " << ok << " / " << x.runs.size() << " |";
    for (int k = 0; k < 2; ++k) {
      const double a = kAccuracies[k];
      const CaseRecord* r = x.cheapest(a, t_end);
      o << " " << (c.ill[k] ? kIll : r ? settingText(*r) + " | " + sci(perSimulatedSecond(*r, t_end)) : notReached(floors, x, a) + " | -") << " |";
      if (loops) o << " " << (r && !c.ill[k] ? loopsCell(*r) : std::string("-")) << " |";
    }
    o << "\n";
  }
  return o.str() + "\n";
}

// Whether eigenmass's fastest route is cheaper than every other owner's, per
// accuracy, said in one line each: with `timed`, the verdict of the
// interleaved rounds with its interval (met, tied, missed), and beside it the
// verdict against the engines' own u' under the in-house integrators alone
// (issue 75, item 5: at 1e-6 rad the win over native engines is the
// integrator's; the -udot rows run the same integrators).
std::string goalLines(const std::vector<std::pair<std::string, Fastest>>& by_owner, double t_end, const Conditioning& c,
                      const Interleaved* timed) {
  std::ostringstream o;
  const auto self = std::find_if(by_owner.begin(), by_owner.end(), [](const auto& p) { return p.first == kInHouseOwner; });
  if (self == by_owner.end()) return "";
  for (int a = 0; a < 2; ++a) {
    if (c.ill[a]) {
      o << "- To " << sci(kAccuracies[a]) << " rad: not judged: ill-conditioned (the reference's sensitivity twin).\n";
      continue;
    }
    if (c.unresolved[a]) {
      o << "- To " << sci(kAccuracies[a]) << " rad: not judged: the reference and its check differ by " << sci(c.check_rad)
        << " rad, more than a tenth of it.\n";
      continue;
    }
    const CaseRecord* mine = self->second.run[a];
    if (!timed) {
      std::vector<std::string> cheaper;
      for (const auto& [owner, f] : by_owner)
        if (owner != kInHouseOwner && f.run[a] && (!mine || perSimulatedSecond(*f.run[a], t_end) < perSimulatedSecond(*mine, t_end)))
          cheaper.push_back(owner + (mine ? " (" + gnum(perSimulatedSecond(*mine, t_end) / perSimulatedSecond(*f.run[a], t_end), 3) + "x cheaper)" : ""));
      o << "- To " << sci(kAccuracies[a]) << " rad: eigenmass's fastest route is "
        << (!mine ? "none (not reached)" : cheaper.empty() ? "the cheapest of all: goal met" : "beaten by " + joined(cheaper) + ": goal missed")
        << ".\n";
      continue;
    }
    o << "- To " << sci(kAccuracies[a]) << " rad: ";
    if (!mine) {
      o << "eigenmass's fastest route is none (not reached).\n";
      continue;
    }
    const Contest all = contestOf(by_owner, a, t_end, false), same = contestOf(by_owner, a, t_end, true);
    o << marginVerdict(all, *timed) << "; against the engines' u' under the same integrators (-udot rows): "
      << (same.others.empty() ? std::string("none reached it") : marginVerdict(same, *timed)) << ".\n";
  }
  return o.str() + "\n";
}

std::string runTable(const std::vector<Route>& routes, double t_end) {
  const bool p = anyOf(routes, &CaseRecord::momentum_p), H = anyOf(routes, &CaseRecord::momentum_H),
             sep = anyOf(routes, &CaseRecord::joint_separation), loops = anyOf(routes, &CaseRecord::loop_position_m);
  std::ostringstream o;
  o << "| method | scheme | setting | status | max pose error (rad) | > 1e-3 rad at (s) | > 0.1 rad at (s) | max dE / E_scale |"
    << (p ? " max dp / p0 |" : "") << (H ? " max dH_c / H_c0 |" : "") << (sep ? " max joint separation (m) |" : "")
    << (loops ? " loops open (m, rad) |" : "") << " CPU s / s |\n|---|---|---|---|---|---|---|---|" << (p ? "---|" : "")
    << (H ? "---|" : "") << (sep ? "---|" : "") << (loops ? "---|" : "") << "---|\n";
  for (const Route& x : routes)
    for (const CaseRecord* r : x.runs) {
      // A run that stopped at t = 0 has no sample to measure: dashes, not zeros.
      const bool none = r->status != Outcome::Ok && r->failure_time.value_or(1) <= 0;
      auto cell = [none](double x) { return none ? std::string("-") : sci(x); };
      o << "| " << x.label() << " | " << r->integrator << " | " << settingText(*r) << " | "
        << (r->status == Outcome::Ok ? std::string(outcomeName(r->status)) : std::string(failureName(r->failure_kind)) + " at " + gnum(r->failure_time.value_or(0), 4) + " s") << " | "
        << cell(r->max_pose) << " | " << when(r->pose_beyond[0]) << " | " << when(r->pose_beyond[1]) << " | " << cell(r->max_energy) << " |";
      if (p) o << " " << cell(r->momentum_p.value_or(NAN)) << " |";
      if (H) o << " " << cell(r->momentum_H.value_or(NAN)) << " |";
      if (sep) o << " " << cell(r->joint_separation.value_or(NAN)) << " |";
      if (loops) o << " " << (none ? std::string("-") : loopsCell(*r)) << " |";
      o << " " << sci(perSimulatedSecond(*r, t_end)) << " |\n";
    }
  return o.str() + "\n";
}

// Per accuracy: each scene's cheapest route and how much dearer the next owner's is; owners that never got there.
std::string cheapestLines(const std::vector<CaseRecord>& rs, const std::vector<std::string>& scenes, double t_end, const Interleaved* timed) {
  std::ostringstream o;
  for (int a = 0; a < 2; ++a) {
    o << "Within " << sci(kAccuracies[a]) << " rad over the horizon, the cheapest route:\n\n";
    std::vector<std::string> owners, reached;
    for (const std::string& s : scenes) {
      const Conditioning cond = conditioningOf(rs, s);
      if (cond.ill[a]) {
        o << "- " << s << ": ill-conditioned (round-off, amplified as the reference's sensitivity twin measures, reaches a tenth of it): no route ranked\n";
        continue;
      }
      if (cond.unresolved[a]) {
        o << "- " << s << ": not resolved (the reference and its check differ by " << sci(cond.check_rad) << " rad): no route ranked\n";
        continue;
      }
      const std::vector<Route> routes = routesOf(rs, s);
      auto by_owner = fastestByOwner(routes, t_end);
      for (const auto& [owner, f] : by_owner) {
        if (std::find(owners.begin(), owners.end(), owner) == owners.end()) owners.push_back(owner);
        if (f.run[a] && std::find(reached.begin(), reached.end(), owner) == reached.end()) reached.push_back(owner);
      }
      by_owner.erase(std::remove_if(by_owner.begin(), by_owner.end(), [&](const auto& p) { return !p.second.run[a]; }), by_owner.end());
      std::stable_sort(by_owner.begin(), by_owner.end(), [&](const auto& x, const auto& y) {
        return perSimulatedSecond(*x.second.run[a], t_end) < perSimulatedSecond(*y.second.run[a], t_end);
      });
      o << "- " << s << ": ";
      if (by_owner.empty()) {
        o << "none\n";
        continue;
      }
      const Fastest& f = by_owner[0].second;
      o << by_owner[0].first << " (" << f.route[a]->label() << " " << f.route[a]->integrator << " " << settingText(*f.run[a])
        << ", " << sci(perSimulatedSecond(*f.run[a], t_end)) << " CPU s / s)";
      if (by_owner.size() > 1)
        o << "; next " << by_owner[1].first << ", "
          << gnum(perSimulatedSecond(*by_owner[1].second.run[a], t_end) / perSimulatedSecond(*f.run[a], t_end), 3) << "x dearer by the medians";
      if (timed) {  // eigenmass's verdict there, from the interleaved rounds
        const Contest c = contestOf(by_owner, a, t_end, false);
        if (c.mine) o << "; eigenmass: " << marginVerdict(c, *timed);
      }
      o << "\n";
    }
    std::vector<std::string> never;
    for (const std::string& w : owners)
      if (std::find(reached.begin(), reached.end(), w) == reached.end()) never.push_back(w);
    o << "- no route within " << sci(kAccuracies[a]) << " rad on any scene: " << (never.empty() ? "none" : joined(never)) << "\n\n";
  }
  return o.str();
}

}  // namespace

std::string routeOwner(const std::string& method) {
  Method m;
  return findMethod(method, m) ? methodOwner(m) : method;
}

bool routeOwningIntegrator(const IntegratorInfo& i) { return i.dae; }

std::string benchmarkOwner(const std::string& method, const std::string& integrator) {
  Integrator i;
  return findIntegrator(integrator, i) && routeOwningIntegrator(info(i)) ? integrator : routeOwner(method);
}

std::string engineStudyScene(const std::vector<CaseRecord>& rs, const std::string& scene, double t_end, double output_dt,
                             double floor, bool judge, const Interleaved* timed) {
  const std::vector<Route> routes = routesOf(rs, scene);
  const auto by_owner = fastestByOwner(routes, t_end);
  const Conditioning cond = conditioningOf(rs, scene);
  const Floors floors = floorsOf(routes, cond.ill);
  std::ostringstream o;
  for (int a = 0; a < 2; ++a)
    if (cond.ill[a])
      o << "**Ill-conditioned at " << sci(kAccuracies[a]) << " rad: " << twinText(*cond.twin)
        << ". An error of that size here is the scene's amplification of round-off, not a method's: no route is ranked "
        << "at " << sci(kAccuracies[a]) << " rad.**\n\n";
  if (cond.twin && !cond.ill[0] && !cond.ill[1])
    o << "Conditioning: " << twinText(*cond.twin) << ": both accuracies are resolved.\n\n";
  for (double a : kAccuracies)
    if (floor > a / 10)
      o << "**The reference and its check differ by " << sci(floor) << " rad, more than a tenth of " << sci(a)
        << " rad: on this scene the " << sci(a) << " columns are not resolved (an error below the floor is the "
        << "reference's as much as the run's).**\n\n";
  o << "#### Each route's cheapest run within 1e-3 and 1e-6 rad over the horizon\n\n" << routeTable(routes, t_end, cond, floors)
    << gridBoundLines(routes, output_dt) << floorLines(floors);
  o << "#### Each owner's fastest route\n\n| owner | fastest within 1e-3 rad | CPU s / s | fastest within 1e-6 rad | CPU s / s |\n"
    << "|---|---|---|---|---|\n";
  for (const auto& [owner, f] : by_owner)
    o << "| " << owner << " | " << routeCell(f, 0, t_end, cond) << " | " << routeCell(f, 1, t_end, cond) << " |\n";
  o << "\n" << (judge ? goalLines(by_owner, t_end, cond, timed) : "- Goals not judged: the study's results are incomplete (above).\n\n");
  o << "#### Every run\n\n" << runTable(routes, t_end);
  return o.str();
}

std::vector<std::string> engineStudyContenders(const std::vector<CaseRecord>& rs, const std::vector<std::string>& scenes, double t_end) {
  std::vector<std::string> out;
  for (const std::string& s : scenes) {
    const auto by_owner = fastestByOwner(routesOf(rs, s), t_end);
    const Conditioning cond = conditioningOf(rs, s);
    for (int a = 0; a < 2; ++a)
      if (cond.judged(a))
        for (bool hybrid_only : {false, true}) addContenders(contestOf(by_owner, a, t_end, hybrid_only), out);
  }
  return out;
}

std::string engineStudySummary(const std::vector<CaseRecord>& rs, const std::vector<std::string>& scenes, double t_end,
                               const Interleaved* timed) {
  struct Tally {
    int reached[2] = {0, 0}, fastest[2] = {0, 0};
    std::vector<double> cost[2];
  };
  std::map<std::string, Tally> tally;
  std::vector<std::string> owners;
  size_t judged[2] = {0, 0};  // scenes where each accuracy is not ill-conditioned
  for (const std::string& s : scenes) {
    const std::vector<Route> routes = routesOf(rs, s);
    const auto by_owner = fastestByOwner(routes, t_end);
    const Conditioning cond = conditioningOf(rs, s);
    for (int a = 0; a < 2; ++a) {
      for (const auto& [owner, f] : by_owner)
        if (std::find(owners.begin(), owners.end(), owner) == owners.end()) owners.push_back(owner);
      if (!cond.judged(a)) continue;  // no route ranked there
      ++judged[a];
      const std::string* best = nullptr;
      double best_cost = INFINITY;
      for (const auto& [owner, f] : by_owner) {
        if (!f.run[a]) continue;
        const double c = perSimulatedSecond(*f.run[a], t_end);
        ++tally[owner].reached[a];
        tally[owner].cost[a].push_back(c);
        if (c < best_cost) best_cost = c, best = &owner;
      }
      if (best) ++tally[*best].fastest[a];
    }
  }
  std::ostringstream o;
  o << cheapestLines(rs, scenes, t_end, timed);
  if (judged[0] < scenes.size() || judged[1] < scenes.size())
    o << "\"of N\" counts the scenes where that accuracy is judged (not ill-conditioned, and resolved by the reference's check): " << judged[0] << " of " << scenes.size()
      << " at 1e-3 rad, " << judged[1] << " of " << scenes.size() << " at 1e-6 rad.\n\n";
  o << "| owner | scenes reached within 1e-3 rad | fastest there | median CPU s / s of its fastest route | scenes reached within "
       "1e-6 rad | fastest there | median CPU s / s |\n|---|---|---|---|---|---|---|\n";
  for (const std::string& w : owners) {
    Tally& t = tally[w];
    o << "| " << w;
    for (int a = 0; a < 2; ++a) {
      std::sort(t.cost[a].begin(), t.cost[a].end());
      const size_t k = t.cost[a].size();
      const double med = k == 0 ? NAN : k % 2 ? t.cost[a][k / 2] : 0.5 * (t.cost[a][k / 2 - 1] + t.cost[a][k / 2]);
      o << " | " << t.reached[a] << " of " << judged[a] << " | " << t.fastest[a] << " | " << sci(med);
    }
    o << " |\n";
  }
  return o.str() + "\n";
}

}  // namespace em
