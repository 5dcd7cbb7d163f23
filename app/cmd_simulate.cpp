// `eigenmass simulate`: one method on one scene, its trajectory as CSV.
#include <cmath>
#include <cstdio>
#include <memory>

#include "app/cli.hpp"
#include "compare/metrics.hpp"
#include "compare/engines.hpp"
#include "solver/text.hpp"

namespace em::cli {

namespace {

struct SimulateArgs {
  SceneArg scene;
  std::string out, method = methodName(Method::Classical), integrator;
  RunSpec spec;  ///< dt and tol as given (or their defaults)
  RunArgs run;
  OutsideArgs outside;  ///< --plugin: then the plugin is the method run
};

void printSummary(const Trajectory& tr, const std::string& path) {
  double drift = 0;  // the energy balance: what the dampers took is not drift
  for (size_t k = 0; k < tr.size(); ++k) drift = std::max(drift, std::abs(tr.energy[k] + tr.dissipated[k] - tr.energy[0]));
  const std::string ended = tr.failed() ? "failed at t = " + gnum(tr.failure_time) + " s (" + tr.failure + "), last sample" : "t";
  std::printf("%s %s/%s: status %s, %s = %.6g s, %ld steps, %ld rhs evaluations, %.3f s CPU\n", tr.scene.c_str(),
              tr.method().c_str(), tr.integrator().c_str(), outcomeName(tr.status()), ended.c_str(), tr.t.back(), tr.steps,
              tr.rhs_evals, tr.run_time_s);
  // %.12g, not %.12f: E(0) of 1e300 J (a spring's k of 1e300) printed 300 digits (issue 73, item 14).
  std::printf("energy: E(0) = %.12g J, max |E(t) + W_diss(t) - E(0)| = %.3e J (relative to %s J: %.3e)", tr.energy[0],
              drift, gnum(energyScale(tr)).c_str(), drift / energyScale(tr));
  if (!tr.dissipated.empty() && tr.dissipated.back() != 0) std::printf(", dissipated W_diss = %.6g J", tr.dissipated.back());
  if (std::isfinite(tr.max_joint_separation))  // a maximal-coordinate engine's (ODE's) joints, loops included
    std::printf("\njoints: their two points drifted apart by up to %.3g m (after every step)", tr.max_joint_separation);
  if (tr.has_loops) {
    const LoopStats& l = tr.loops;
    std::printf("\nloops: largest violation %.3g m and %.3g rad, %.3g m/s and %.3g rad/s", l.position_m, l.position_rad, l.velocity_m,
                l.velocity_rad);
    if (l.rank_max >= 0) std::printf("; rank %d", l.rank_max);
    else std::printf(" (at the samples, by eigenmass's g(q); the engine closes the loops its own way)");
    if (!l.rank_drop_times.empty()) {  // singular positions: where the route may change branch
      std::printf("; rank fell below %d (a singular position) %zu time%s, first at t = %.6g s", l.rank_start, l.rank_drop_times.size(),
                  l.rank_drop_times.size() == 1 ? "" : "s", l.rank_drop_times.front());
    }
    if (l.projections)
      std::printf("; %ld projections, %ld Gauss-Newton iterations, %ld unconverged", l.projections, l.projection_iterations,
                  l.projections_unconverged);
    if (l.newton_solves)
      std::printf("; %ld Newton solves, %ld iterations, %ld unconverged", l.newton_solves, l.newton_iterations, l.newton_unconverged);
    if (l.repartitions) {
      std::printf("; re-partitioned %ld times, at t =", l.repartitions);
      for (double t : l.repartition_times) std::printf(" %.6g", t);
      if (static_cast<long>(l.repartition_times.size()) < l.repartitions) std::printf(" ...");
      std::printf(" s");
    }
  }
  if (regularOutput(path)) std::printf("\ntrajectory: %s (run, status and provenance: %s.json)\n", path.c_str(), path.c_str());
  else std::printf("\ntrajectory: %s (run, status and provenance: on standard error)\n", path.c_str());
}

// The run's settings checked once, a refusal told as the option the user typed.
CheckedRunSpec checkedOption(const RunSpec& spec) {
  try {
    return checked(spec);
  } catch (const SettingError& e) {
    throw e.as(e.option());
  }
}

int runSimulate(const SimulateArgs& a, const CLI::App& cmd) {
  const Scene scene = a.scene.load();
  checkInitialState(scene);
  refuseUnreadLoopOptions(cmd, scene.model);
  if (a.outside.plugins.size() > 1) throw std::invalid_argument("--plugin: simulate runs one method; one plugin at a time");
  if (!a.outside.plugins.empty() && cmd.count("--method"))
    throw std::invalid_argument("--method: with --plugin, the plugin is the method run");
  const std::vector<std::string> added = a.outside.load(scene);
  const std::string method = added.empty() ? a.method : added[0];
  const std::string path = a.out.empty() ? "out/" + scene.model.name + "." + method + ".csv" : a.out;
  std::vector<std::string> inputs = a.outside.files();
  inputs.push_back(a.scene.path);
  prepareOutput("--out", path, inputs, {path + ".json"});  // writeTrajectory's sidecar
  RunSpec s = a.spec;
  a.run.applyTo(s);
  s.method = parseMethod(method);
  // --tol alone selects an adaptive integrator for the in-house methods.
  s.integrator = a.integrator.empty() ? chosenIntegrator(s.engine(), cmd.count("--tol") > 0) : parseIntegrator(a.integrator);
  // A setting the chosen integrator does not read is refused, not ignored (mujoco has no adaptive scheme).
  refuseUnreadSetting(cmd, s.integrator, "--dt", "--tol");
  refuseUnreadRunOptions(cmd, {s.method}, s.engine() == Engine::InHouse && !s.fixedStep());
  refuseUnreadFormulationOptions(cmd, {s.method}, s.integrator, s.options.loops.formulation, scene.model);
  const Trajectory tr = runTrajectory(scene.model, checkedOption(onGrid(s, scene, a.run.asked(cmd))));
  writeTrajectory(tr, path, &scene.source);
  if (const auto& a = scene.source.assembly)
    std::printf("assembled: the written start was open by %.3g (m or rad) and %.3g (m/s or rad/s); q0 moved by at most %.3g, "
                "u0 by %.3g, in %d Gauss-Newton steps\n", a->gap, a->velocity_gap, a->moved_q, a->moved_u, a->iterations);
  printSummary(tr, path);
  if (const std::string note = gridSetStepsNote(tr, tr.run); !note.empty()) std::printf("steps: %s\n", note.c_str());
  return tr.failed() ? 1 : 0;
}

// "In-house: rk4, ... (default rk4); simbody: rkmerson, ... (default rkmerson); mujoco: ..."
std::string integratorsHelp() {
  std::string help;
  for (const EngineInfo& e : engineTable()) {
    const bool fixed_only = !hasAdaptiveScheme(e.id);
    help += std::string(help.empty() ? "In-house" : std::string("; ") + e.name) + ": " + joined(integratorNames(e.id)) +
            " (default " + integratorName(e.fixed_default) + (fixed_only ? ", fixed step --dt)" : ")");
  }
  return help;
}

}  // namespace

void addSimulate(CLI::App& app) {
  auto* cmd = app.add_subcommand("simulate", "Integrate a scene with one method and write its trajectory as CSV");
  auto a = std::make_shared<SimulateArgs>();
  addSceneArg(cmd, a->scene);
  cmd->add_option("--method", a->method, helpWithNames("Method", methodNames()))
      ->check(methodValidator())
      ->capture_default_str();
  cmd->add_option("--integrator", a->integrator, integratorsHelp())->check(integratorValidator());
  auto* dt = cmd->add_option("--dt", a->spec.dt, "Fixed step of fixed-step integrators (s)")
                 ->check(positiveFinite())
                 ->capture_default_str();
  auto* tol = cmd->add_option("--tol", a->spec.tol, "Absolute and relative tolerance of adaptive integrators (another engine's: its accuracy)")
                  ->check(positiveFinite())
                  ->capture_default_str();
  dt->excludes(tol);
  addRunOptions(cmd, a->run, "Sampling interval (s)");
  addOutsideOptions(cmd, a->outside, false);
  cmd->add_option("--out", a->out, "CSV file to write; default out/<scene>.<method>.csv");
  cmd->callback([cmd, a] { guarded([&] { return runSimulate(*a, *cmd); }); });
}

}  // namespace em::cli
