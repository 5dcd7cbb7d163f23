#include "compare/commands.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "compare/comparison.hpp"
#include "compare/gate.hpp"
#include "compare/precision.hpp"
#include "compare/report.hpp"
#include "compare/runner.hpp"
#include "solver/scene.hpp"

namespace em::cli {

namespace {

int g_exit = 0;

nlohmann::json toJson(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

nlohmann::json toJson(const Eigen::MatrixXd& A) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < A.rows(); ++i) rows.push_back(toJson(Eigen::VectorXd(A.row(i).transpose())));
  return rows;
}

// Every subcommand body runs here: bad input or options end in one line on
// stderr and exit status 2, never a crash.
template <class F>
void guarded(F&& f) {
  try {
    g_exit = f();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "eigenmass: error: %s\n", e.what());
    g_exit = 2;
  }
}

void ensureParentDir(const std::string& path) {
  const auto dir = std::filesystem::path(path).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir);
}

}  // namespace

int exitCode() { return g_exit; }

void addEquations(CLI::App& app) {
  auto* cmd = app.add_subcommand("equations", "Print A, B, u', energy and eigenvalues of A at the scene's initial state (JSON)");
  auto scene = std::make_shared<std::string>();
  auto engine = std::make_shared<std::string>("inhouse");
  cmd->add_option("scene", *scene, "Scene file (eigenmass-scene/1)")->required();
  cmd->add_option("--engine", *engine, "Who forms the equations: inhouse (Wittenburg) or simbody")
      ->check(CLI::IsMember({"inhouse", "simbody"}))
      ->capture_default_str();
  cmd->callback([=] {
    guarded([&] {
      const Model m = loadScene(*scene);
      const Equations e = *engine == "simbody" ? simbodyEquations(m) : inhouseEquations(m);
      nlohmann::json j;
      j["scene"] = m.name;
      j["engine"] = *engine;
      j["nq"] = e.nq;
      j["nu"] = e.nu;
      j["A"] = toJson(e.A);
      j["B"] = toJson(e.B);
      j["udot"] = toJson(e.udot);
      j["energy"] = {{"kinetic", e.kinetic}, {"potential", e.potential}, {"total", e.kinetic + e.potential}};
      j["eigenvalues"] = toJson(e.eigenvalues);
      std::cout << j.dump(2) << "\n";
      return 0;
    });
  });
}

void addSimulate(CLI::App& app) {
  auto* cmd = app.add_subcommand("simulate", "Integrate a scene with one method and write its trajectory as CSV");
  auto scene = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto spec = std::make_shared<RunSpec>();
  cmd->add_option("scene", *scene, "Scene file (eigenmass-scene/1)")->required();
  cmd->add_option("--method", spec->method, std::string("Method: ") + knownMethods())->capture_default_str();
  cmd->add_option("--integrator", spec->integrator,
                  "In-house: rk4 (fixed step, default), rkf45, rk8pd, bsimp (implicit, stiff); simbody: rkmerson "
                  "(default), rk3, cpodes");
  auto* dt = cmd->add_option("--dt", spec->dt, "Fixed step of rk4 (s)")->capture_default_str();
  auto* tol = cmd->add_option("--tol", spec->tol, "Absolute and relative tolerance of adaptive integrators (Simbody: accuracy)")
                  ->capture_default_str();
  dt->excludes(tol);
  cmd->add_option("--t-end", spec->t_end, "End time (s); default: the scene's simulate.t_end, else 10");
  cmd->add_option("--output-dt", spec->output_dt, "Sampling interval (s); default: the scene's simulate.output_dt, else 0.01");
  cmd->add_option("--out", *out, "CSV file to write; default out/<scene>.<method>.csv");
  cmd->callback([=] {
    guarded([&] {
      const Model m = loadScene(*scene);
      RunSpec s = *spec;
      // --tol alone selects an adaptive integrator for the in-house methods.
      if (s.integrator.empty() && s.method != "simbody" && cmd->count("--tol")) s.integrator = "rk8pd";
      const Trajectory tr = runMethod(m, s);
      const std::string path = out->empty() ? "out/" + m.name + "." + s.method + ".csv" : *out;
      ensureParentDir(path);
      writeCsv(tr, path);
      double drift = 0;
      for (double E : tr.energy) drift = std::max(drift, std::abs(E - tr.energy[0]));
      std::printf("%s %s/%s: status %s%s, t = %.6g s, %ld steps, %ld rhs evaluations, %.3f s CPU\n", m.name.c_str(),
                  tr.method.c_str(), tr.integrator.c_str(), tr.status.c_str(),
                  tr.failed() ? (" (" + tr.failure + ")").c_str() : "", tr.t.back(), tr.steps, tr.rhs_evals,
                  tr.run_time_s);
      std::printf("energy: E(0) = %.12f J, max |E(t) - E(0)| = %.3e J (relative %.3e)\n", tr.energy[0], drift,
                  drift / std::abs(tr.energy[0]));
      std::printf("trajectory: %s\n", path.c_str());
      return tr.failed() ? 1 : 0;
    });
  });
}

namespace {

struct CompareArgs {
  std::string scene, out, csv_dir, gate, reference = "simbody", reference_integrator;
  std::vector<std::string> methods = CompareOptions().methods;
  CompareOptions opt;
};

void progress(const std::string& what) { std::fprintf(stderr, "running %s ...\n", what.c_str()); }

int runCompare(CompareArgs a, const CLI::App& cmd) {
  // Bad input fails here, before any simulation.
  const Model m = loadScene(a.scene);
  const Tolerances tol = a.gate.empty() ? Tolerances{} : loadTolerances(a.gate);
  CompareOptions& o = a.opt;
  o.methods = a.methods;
  o.reference.method = a.reference;
  o.reference.integrator = !a.reference_integrator.empty() ? a.reference_integrator
                           : a.reference == "simbody"    ? "rkmerson"
                                                         : "rk8pd";
  if (cmd.count("--tol") && !cmd.count("--integrator")) o.inhouse.integrator = "rk8pd";
  const ComparisonResult r = runComparison(m, a.scene, o, progress);
  nlohmann::json gate = nullptr;
  GateResult g;
  if (!a.gate.empty()) {
    g = evaluateGate(r, tol);
    gate = gateJson(g);
  }
  const std::string out = a.out.empty() ? "out/" + m.name + ".report.json" : a.out;
  ensureParentDir(out);
  if (!a.csv_dir.empty()) {
    std::filesystem::create_directories(a.csv_dir);
    writeCsv(r.reference, a.csv_dir + "/reference.csv");
    for (const Trajectory& t : r.runs) writeCsv(t, a.csv_dir + "/" + t.method + ".csv");
  }
  writeJsonAtomic(makeReport(r, gate), out);
  std::printf("%s: %d bodies, %d speeds, t_end %g s, output every %g s\n", m.name.c_str(), m.n(), m.nu, r.t_end,
              r.output_dt);
  std::fputs(summaryTable(r).c_str(), stdout);
  std::printf("report: %s\n", out.c_str());
  if (a.gate.empty()) return 0;
  if (g.passed) {
    std::printf("gate passed: %zu checks (%s)\n", g.checks.size(), a.gate.c_str());
    return 0;
  }
  std::fputs(brokenChecks(g).c_str(), stdout);
  return 1;
}

}  // namespace

void addCompare(CLI::App& app) {
  auto* cmd = app.add_subcommand("compare", "Run several methods side by side against a reference and write a JSON report");
  auto a = std::make_shared<CompareArgs>();
  CompareOptions& o = a->opt;
  cmd->add_option("scene", a->scene, "Scene file (eigenmass-scene/1)")->required();
  cmd->add_option("--methods", a->methods, std::string("Methods to compare, comma-separated: ") + knownMethods())
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--reference", a->reference, "Reference engine: simbody or classical (in-house)")
      ->check(CLI::IsMember({"simbody", "classical"}))
      ->capture_default_str();
  cmd->add_option("--reference-integrator", a->reference_integrator,
                  "Integrator of the reference (default rkmerson for simbody, rk8pd for classical)");
  cmd->add_option("--reference-tol", o.reference.tol, "Tolerance (accuracy) of the reference; its horizon run uses 1/100 of it")
      ->capture_default_str();
  cmd->add_option("--integrator", o.inhouse.integrator, "Integrator of the in-house methods: rk4, rkf45, rk8pd, bsimp")
      ->capture_default_str();
  auto* dt = cmd->add_option("--dt", o.inhouse.dt, "Fixed step of rk4 for the in-house methods (s)")->capture_default_str();
  auto* tol = cmd->add_option("--tol", o.inhouse.tol, "Tolerance of adaptive in-house integrators (alone: selects rk8pd)")
                  ->capture_default_str();
  dt->excludes(tol);
  cmd->add_option("--simbody-integrator", o.simbody.integrator, "Integrator of the compared simbody method: rkmerson, rk3, cpodes")
      ->capture_default_str();
  cmd->add_option("--simbody-tol", o.simbody.tol, "Accuracy of the compared simbody method")->capture_default_str();
  cmd->add_option("--t-end", o.t_end, "End time (s); default: the scene's simulate.t_end");
  cmd->add_option("--output-dt", o.output_dt, "Common output grid (s); default: the scene's simulate.output_dt");
  cmd->add_option("--thresholds", o.thresholds, "Pose-error thresholds of the divergence times (rad), comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--out", a->out, "Report file; default out/<scene>.report.json");
  cmd->add_option("--csv-dir", a->csv_dir, "Also write every trajectory (and the reference) as CSV into this folder");
  cmd->add_option("--gate", a->gate, "Tolerance file (data/tolerances.json): exit 1 and list the broken bounds if any");
  cmd->callback([cmd, a] { guarded([&] { return runCompare(*a, *cmd); }); });
}

void addPrecision(CLI::App& app) {
  auto* cmd = app.add_subcommand("precision", "Work-precision: each method at several steps or tolerances, error against CPU time");
  auto scene = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto o = std::make_shared<PrecisionOptions>();
  cmd->add_option("scene", *scene, "Scene file (eigenmass-scene/1)")->required();
  cmd->add_option("--methods", o->methods, std::string("Methods, comma-separated: ") + knownMethods())
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--integrator", o->integrator, "rk4 (settings are steps dt) or rkf45, rk8pd, bsimp (settings are tolerances)")
      ->capture_default_str();
  cmd->add_option("--settings", o->settings, "Steps (rk4) or tolerances, comma-separated")->delimiter(',')->capture_default_str();
  cmd->add_option("--reference-tol", o->reference.tol, "Accuracy of the Simbody RK-Merson reference")->capture_default_str();
  cmd->add_option("--t-end", o->t_end, "End time (s); default: the scene's simulate.t_end");
  cmd->add_option("--output-dt", o->output_dt,
                  "Sampling interval (s), a multiple of every step; default: the scene's simulate.output_dt");
  cmd->add_option("--out", *out, "JSON file to write; default out/<scene>.precision.json");
  cmd->callback([=] {
    guarded([&] {
      const Model m = loadScene(*scene);
      const PrecisionResult r = runPrecision(m, *o, progress);
      const std::string path = out->empty() ? "out/" + m.name + ".precision.json" : *out;
      ensureParentDir(path);
      writeJsonAtomic(precisionJson(r), path);
      std::fputs(precisionTable(r).c_str(), stdout);
      std::printf("report: %s\n", path.c_str());
      return 0;
    });
  });
}

}  // namespace em::cli
