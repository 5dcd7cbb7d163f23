// `eigenmass crosscheck`: the in-house A, B and u' against every engine that
// gives them (Simbody, MuJoCo, ...) at the initial state and at random states (docs/urdf.md).
#include <algorithm>
#include <cstdio>
#include <map>
#include <string>
#include <memory>

#include "app/cli.hpp"
#include "compare/crosscheck.hpp"
#include "reference/engine.hpp"

namespace em::cli {

namespace {

struct CrossCheckArgs {
  SceneArg scene;
  int states = 20;
  unsigned seed = 1;
  double tol = 1e-7;
  OutsideArgs outside;  ///< --plugin: its u' at the same states
};

// One entry of the table: "-" where the row gives none, a "*" after a value
// that is eigenmass's own code in the engine's row (not independent).
std::string cell(double value, bool given, const std::string& shared) {
  if (!given) return "-";
  char text[32];
  std::snprintf(text, sizeof text, "%.2e%s", value, shared.empty() ? " " : "*");
  return text;
}

// "independent agreement within 1e-07: A by simbody, mujoco; B by ...; u' by ...":
// the engines (not their "-mass" twins, not plugins) whose own entries, judged
// and not eigenmass's code, are within tol: the evidence the in-house equations stand on.
std::string independentAgreement(const std::vector<CrossCheckRow>& rows, const std::map<std::string, EquationsDependence>& dependent,
                                 const std::vector<std::string>& unjudged_udot, double tol) {
  std::string A, B, udot;
  auto add = [](std::string& list, const std::string& name) { list += (list.empty() ? "" : ", ") + name; };
  for (const CrossCheckRow& r : rows) {
    bool engine = false;
    for (Engine e : otherEngines()) engine = engine || r.engine == engineName(e);
    if (!engine) continue;
    const auto d = dependent.find(r.engine);
    const EquationsDependence shared = d == dependent.end() ? EquationsDependence{} : d->second;
    const bool udot_judged = std::count(unjudged_udot.begin(), unjudged_udot.end(), r.engine) == 0;
    if (shared.A.empty() && r.A <= tol) add(A, r.engine);
    if (!r.A_only && shared.B.empty() && r.B <= tol) add(B, r.engine);
    if (!r.A_only && udot_judged && shared.udot.empty() && r.udot <= tol) add(udot, r.engine);
  }
  char head[64];
  std::snprintf(head, sizeof head, "independent agreement within %.0e: ", tol);
  auto none = [](const std::string& s) { return s.empty() ? std::string("none") : s; };
  return head + ("A by " + none(A)) + "; B by " + none(B) + "; u' by " + none(udot);
}

int runCrossCheck(const CrossCheckArgs& a) {
  const Scene scene = a.scene.load();
  checkInitialState(scene);
  std::vector<Method> plugins;
  for (const std::string& name : a.outside.load(scene)) plugins.push_back(parseMethod(name));
  const CrossCheck c = crossCheck(scene, a.scene.urdf, a.states, a.seed, plugins);
  std::printf("%s (%s): %d speeds; differences relative to the in-house value's largest entry\n",
              scene.model.name.c_str(), scene.source.format.c_str(), scene.model.nu);
  for (const std::string& n : scene.source.notes) std::printf("import note: %s\n", n.c_str());
  for (const std::string& s : c.skipped) std::printf("skipped %s\n", s.c_str());
  for (const std::string& s : c.notes) std::printf("note: %s\n", s.c_str());
  std::printf("%-12s %10s %10s %10s\n", "engine", "A ", "B ", "u' ");
  // Judged: every engine's A, B and u', but the raw u' of an engine that
  // compiles its own masses (MuJoCo): that carries its inertia rounding
  // amplified by up to cond(A) (printed, explained in docs/urdf.md); its
  // "-mass" row, given those masses, is judged whole.
  std::vector<std::string> rows, unjudged_udot;
  const bool mechanism = scene.model.isMechanism();
  for (Engine e : otherEngines()) {
    const std::string name = engineName(e);
    rows.push_back(name);
    if (engineCode(e).mass_note && !mechanism) rows.push_back(massRowName(name)), unjudged_udot.push_back(name);
    if (engineCode(e).soft_closures && mechanism) unjudged_udot.push_back(name);  // soft closures: u' printed, not judged
  }
  for (Method p : plugins) {  // a plugin's u' against the in-house one, then against each engine's
    rows.emplace_back(methodName(p));
    for (Engine e : otherEngines())
      if (engineCode(e).model) rows.push_back(std::string(methodName(p)) + "/" + engineName(e));
  }
  std::vector<CrossCheckRow> worst_of;  // each printed row's largest entries over the states
  for (const std::string& engine : rows) {
    CrossCheckRow worst{0, engine};
    bool any = false;
    for (const CrossCheckRow& r : c.rows)
      if (r.engine == engine) {
        any = true;
        worst.udot_only = r.udot_only, worst.A_only = r.A_only;
        worst.A = std::max(worst.A, r.A), worst.B = std::max(worst.B, r.B), worst.udot = std::max(worst.udot, r.udot);
      }
    if (!any) continue;
    worst_of.push_back(worst);
    const auto d = c.dependent.find(engine);
    const EquationsDependence shared = d == c.dependent.end() ? EquationsDependence{} : d->second;
    std::printf("%-12s %10s %10s %10s\n", engine.c_str(), cell(worst.A, !worst.udot_only, shared.A).c_str(),
                cell(worst.B, !worst.udot_only && !worst.A_only, shared.B).c_str(),
                cell(worst.udot, !worst.A_only, shared.udot).c_str());
  }
  for (const auto& [row, d] : c.dependent) {  // one line per reason, naming the entries it covers
    // Only the entries the table shows: a footnote beside a "-" cell (issue 73's doubtful list) names nothing printed.
    const auto printed = std::find_if(worst_of.begin(), worst_of.end(), [&](const CrossCheckRow& w) { return w.engine == row; });
    if (printed == worst_of.end()) continue;
    const bool shows_A = !printed->udot_only, shows_B = !printed->udot_only && !printed->A_only, shows_udot = !printed->A_only;
    std::vector<std::pair<std::string, std::string>> lines;  // (entries, why)
    for (const auto& [entry, why] : {std::pair<std::string, std::string>{"A", shows_A ? d.A : ""}, {"B", shows_B ? d.B : ""},
                                     {"u'", shows_udot ? d.udot : ""}}) {
      if (why.empty()) continue;
      auto same = std::find_if(lines.begin(), lines.end(), [&](const auto& l) { return l.second == why; });
      if (same != lines.end()) same->first += ", " + entry;
      else lines.emplace_back(entry, why);
    }
    for (const auto& [entries, why] : lines) std::printf("(* %s %s, not independent: %s)\n", row.c_str(), entries.c_str(), why.c_str());
  }
  for (Engine e : otherEngines()) {
    if (const char* note = engineCode(e).mass_note; note && !mechanism) std::printf("(%s: %s)\n", massRowName(engineName(e)).c_str(), note);
    if (const char* note = engineCode(e).soft_closures; note && mechanism) std::printf("(%s: %s)\n", engineName(e), note);
    if (const char* note = engineCode(e).mechanism_state; note && mechanism) std::printf("(%s: %s)\n", engineName(e), note);
    if (const char* note = engineCode(e).equations_note) std::printf("(%s: %s)\n", engineName(e), note);
  }
  double worst = 0;
  for (const CrossCheckRow& r : c.rows) {
    // (a plugin's u' against such an engine's, "<plugin>/<engine>", carries the same rounding)
    const std::string engine = r.engine.substr(r.engine.find('/') + 1);
    const bool raw_udot_aside = std::count(unjudged_udot.begin(), unjudged_udot.end(), engine) > 0;
    worst = std::max(worst, raw_udot_aside ? std::max(r.A, r.B) : r.worst());
  }
  std::printf("%s\n", independentAgreement(worst_of, c.dependent, unjudged_udot, a.tol).c_str());
  std::printf("largest judged difference over the initial state and %d random states (seed %u): %.2e, %s %.0e\n",
              a.states, a.seed, worst, worst <= a.tol ? "within" : "BEYOND", a.tol);
  return worst <= a.tol ? 0 : 1;
}

}  // namespace

void addCrossCheck(CLI::App& app) {
  auto* cmd = app.add_subcommand("crosscheck", "Compare the in-house A, B and u' with every engine's that gives them (Simbody, MuJoCo, ...) at random states");
  auto a = std::make_shared<CrossCheckArgs>();
  addSceneArg(cmd, a->scene);
  cmd->add_option("--states", a->states, "Random states after the initial one")->check(CLI::Range(0, 100000))->capture_default_str();
  cmd->add_option("--seed", a->seed, "Seed of the random states")->capture_default_str();
  cmd->add_option("--tol", a->tol, "Largest relative difference accepted (exit status 1 beyond)")
      ->check(positiveFinite())
      ->capture_default_str();
  addOutsideOptions(cmd, a->outside, false);
  cmd->callback([a] { guarded([&] { return runCrossCheck(*a); }); });
}

}  // namespace em::cli
