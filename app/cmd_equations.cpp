// `eigenmass equations`: A, B, u', energy and eigenvalues at the initial state.
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "compare/engines.hpp"
#include "reference/engine.hpp"

namespace em::cli {

namespace {

nlohmann::json toJson(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

nlohmann::json toJson(const Eigen::MatrixXd& A) {
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < A.rows(); ++i) rows.push_back(toJson(Eigen::VectorXd(A.row(i).transpose())));
  return rows;
}

// A mechanism's closures at the state: G, its rank, and per loop its rows' gaps
// g and multipliers lambda (theory.md eq. (M7)); udot is then the constrained u'.
nlohmann::json loopsJson(const Model& m, const Equations& e) {
  nlohmann::json loops = nlohmann::json::array();
  int row = 0;
  for (const Loop& l : m.loops) {
    const int n = loopRow(l.type).equations;
    loops.push_back({{"name", l.name}, {"type", loopRow(l.type).name}, {"rows", {row, row + n}},
                     {"g", toJson(Eigen::VectorXd(e.g.segment(row, n)))},
                     {"lambda", toJson(Eigen::VectorXd(e.lambda.segment(row, n)))}});
    row += n;
  }
  return {{"G", toJson(e.G)},
          {"rank", e.rank},
          {"rows", e.G.rows()},
          {"lambda_note", "lambda: the force on body_a's point (N; a direction row's moment, N m), the least-norm one on redundant rows"},
          {"closures", loops}};
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
  if (e.has_loops) j["loops"] = loopsJson(m, e);
  // An engine whose u' of a mechanism is not the exact constrained one says so
  // beside it (issue 73, item 13: MuJoCo's soft closures were 21 % off on a Watt six-bar).
  if (engine != Engine::InHouse && !m.loops.empty()) {
    const EngineCode& code = engineCode(engine);
    if (code.soft_closures) j["udot_note"] = std::string("not the constrained u': ") + code.soft_closures;
    else if (code.mechanism_state) j["udot_note"] = std::string("the tree's alone: ") + code.mechanism_state;
  }
  std::cout << j.dump(2) << "\n";
  return 0;
}

}  // namespace

void addEquations(CLI::App& app) {
  auto* cmd = app.add_subcommand("equations", "Print A, B, u', energy and eigenvalues of A at the scene's initial state (JSON); for a mechanism also G, its rank "
                                               "and the multipliers lambda, and u' is the constrained one (an engine whose u' is not says so in udot_note)");
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
