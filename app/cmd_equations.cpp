// `eigenmass equations`: A, B, u', energy and eigenvalues at the initial state.
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "compare/engines.hpp"

namespace em::cli {

namespace {

nlohmann::json toJson(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

nlohmann::json toJson(const Eigen::MatrixXd& A) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < A.rows(); ++i) rows.push_back(toJson(Eigen::VectorXd(A.row(i).transpose())));
  return rows;
}

int printEquations(const SceneArg& file, Engine engine) {
  const Scene scene = file.load();
  checkInitialState(scene);
  const Model& m = scene.model;
  const Equations e = engineEquations(m, engine);
  nlohmann::json j;
  j["scene"] = m.name;
  j["engine"] = engineName(engine);
  j["nq"] = e.nq;
  j["nu"] = e.nu;
  j["A"] = toJson(e.A);
  j["B"] = toJson(e.B);
  j["udot"] = toJson(e.udot);
  j["energy"] = {{"kinetic", e.kinetic}, {"potential", e.potential}, {"total", e.kinetic + e.potential}};
  j["eigenvalues"] = toJson(e.eigenvalues);
  std::cout << j.dump(2) << "\n";
  return 0;
}

}  // namespace

void addEquations(CLI::App& app) {
  auto* cmd = app.add_subcommand("equations", "Print A, B, u', energy and eigenvalues of A at the scene's initial state (JSON)");
  auto scene = std::make_shared<SceneArg>();
  auto engine = std::make_shared<std::string>(engineName(Engine::InHouse));
  addSceneArg(cmd, *scene);
  std::vector<std::string> engines;
  for (Engine e : enginesWithEquations()) engines.emplace_back(engineName(e));
  cmd->add_option("--engine", *engine, helpWithNames("Who forms the equations (inhouse: Wittenburg)", engines))
      ->check(CLI::IsMember(engines))
      ->capture_default_str();
  cmd->callback([=] { guarded([&] { return printEquations(*scene, parseEngine(*engine)); }); });
}

}  // namespace em::cli
