#include "compare/commands.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

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

void addCompare(CLI::App&) {}

}  // namespace em::cli
