// `eigenmass precision`: each method at several steps or tolerances, error against CPU time.
#include <cmath>
#include <cstdio>
#include <memory>

#include "app/cli.hpp"
#include "compare/precision.hpp"
#include "compare/report.hpp"

namespace em::cli {

namespace {

struct PrecisionArgs {
  SceneArg scene;
  std::string out, integrator = integratorName(Integrator::RK4);
  std::vector<std::string> methods;
  RunArgs run;
  OutsideArgs outside;  ///< --plugin: measured beside --methods
  PrecisionOptions opt;
};

int runPrecisionCommand(const PrecisionArgs& a, const CLI::App& cmd) {
  refuseDuplicates("--settings", a.opt.settings);
  const Scene scene = a.scene.load();
  checkInitialState(scene);
  const std::string path = a.out.empty() ? "out/" + scene.model.name + ".precision.json" : a.out;
  std::vector<std::string> inputs = a.outside.files();
  inputs.push_back(a.scene.path);
  prepareOutput("--out", path, inputs);
  const std::vector<std::string> added = a.outside.load(scene);
  PrecisionOptions o = a.opt;
  a.run.applyTo(o.reference.options);
  a.run.applyTo(o.options);
  o.methods.clear();
  for (const std::string& name : a.methods) o.methods.push_back(parseMethod(name));
  for (const std::string& name : added) o.methods.push_back(parseMethod(name));
  o.integrator = parseIntegrator(a.integrator);
  refuseUnreadRunOptions(cmd, o.methods, !info(o.integrator).fixed_step);
  o.grid = a.run.asked(cmd);
  const PrecisionResult r = runPrecision(scene, o, progress);
  writeJsonAtomic(precisionJson(r), path);
  std::fputs(precisionTable(r).c_str(), stdout);
  std::printf("report: %s\n", path.c_str());
  return 0;
}

}  // namespace

void addPrecision(CLI::App& app) {
  auto* cmd = app.add_subcommand("precision", "Work-precision: each method at several steps or tolerances, error against CPU time");
  auto a = std::make_shared<PrecisionArgs>();
  for (Method m : a->opt.methods) a->methods.push_back(methodName(m));
  addSceneArg(cmd, a->scene);
  cmd->add_option("--methods", a->methods, helpWithNames("Methods, comma-separated", methodNames()))
      ->delimiter(',')
      ->check(methodValidator())
      ->capture_default_str();
  std::vector<std::string> fixed, adaptive;  // the in-house schemes, by what --settings means for them
  for (const std::string& n : integratorNames(Engine::InHouse))
    (info(parseIntegrator(n)).fixed_step ? fixed : adaptive).push_back(n);
  cmd->add_option("--integrator", a->integrator,
                  "In-house integrator: fixed-step " + joined(fixed) + " (--settings are steps dt) or adaptive " +
                      joined(adaptive) + " (--settings are tolerances)")
      ->check(integratorValidator(Engine::InHouse))
      ->capture_default_str();
  cmd->add_option("--settings", a->opt.settings, "Steps (fixed-step integrators) or tolerances, comma-separated")
      ->delimiter(',')
      ->check(positiveFinite())
      ->capture_default_str();
  cmd->add_option("--reference-tol", a->opt.reference.tol,
                  std::string("Accuracy of the reference, ") + methodName(a->opt.reference.method) + " " + integratorName(a->opt.reference.integrator))
      ->check(positiveFinite())
      ->capture_default_str();
  addRunOptions(cmd, a->run, "Sampling interval (s), a multiple of every step");
  addOutsideOptions(cmd, a->outside, false);
  cmd->add_option("--out", a->out, "JSON file to write; default out/<scene>.precision.json");
  cmd->callback([cmd, a] { guarded([&] { return runPrecisionCommand(*a, *cmd); }); });
}

}  // namespace em::cli
