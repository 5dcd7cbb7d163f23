#include "compare/crosscheck.hpp"

#include "compare/engines.hpp"

#include <memory>
#include <optional>
#include <random>

#include "io/json_input.hpp"
#include "outside/plugin.hpp"
#include "reference/engine.hpp"
#include "solver/formation.hpp"
#include "solver/mechanism/projection.hpp"

namespace em {

namespace {

struct Inhouse {
  Eigen::MatrixXd A;
  Eigen::VectorXd B, udot;
  double udot_scale = 0;  ///< what u' differences are relative to (> 0)
};

// A and B are the tree's (every engine's mass matrix and right-hand side
// ignore constraints); u' is the constrained one on a mechanism (theory.md
// eq. (M7)), which is what an engine that closes the loops integrates.
Inhouse inhouseAt(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  Workspace ws(m);
  formEquations(m, q.data(), u.data(), ws);
  const Eigen::VectorXd free = ws.A.llt().solve(ws.B);
  const double free_scale = free.cwiseAbs().maxCoeff();
  if (m.loops.empty()) return {ws.A, ws.B, free, free_scale};
  // Relative to the larger of the constrained and the free u': the
  // constrained solve's round-off scales with the forces, and at a state where
  // the loops cancel them (A02's cranks upright: u' ~ 1e-16) a difference
  // relative to u' alone would be round-off over round-off.
  const Eigen::VectorXd udot = constrainedAt(m, ws, u.data()).udot;
  return {ws.A, ws.B, udot, std::max(udot.cwiseAbs().maxCoeff(), free_scale)};
}

// An engine's model as it can take the scene: its own URDF reader, else the
// Model; where its reader cannot be used, the Model, and a note saying so.
std::unique_ptr<EngineModel> engineModel(Engine e, const Scene& scene, const UrdfOptions& urdf,
                                         std::vector<std::string>& notes) {
  const EngineCode& row = engineCode(e);
  if (scene.source.format != "urdf" || !row.urdf) return row.model(scene.model);
  const UrdfSource source{readFile(scene.source.file, "URDF file"), scene.source_joints, urdf.lock_joints,
                          urdf.balance_inertia, urdf.floating_base ? scene.source_joints.front() : ""};  // the free root's joint comes first (io/urdf.cpp)
  try {
    return row.urdf(scene.model, source);
  } catch (const std::runtime_error& ex) {
    notes.push_back(std::string(engineName(e)) + ": its own URDF reading is not used (" + ex.what() +
                    "); its rows are the imported Model built in " + engineName(e));
    return row.model(scene.model);
  }
}

// The model with an engine's compiled mass properties in place of the in-house
// ones, joint points kept: what remains between it and the engine is not inertia.
Model withMass(const Model& m, const std::vector<CompiledMass>& mj) {
  std::vector<Vec3> point(m.n()), cm_mj(m.n());  // joint point and the engine's CM, world, zero configuration
  std::vector<Vec3> cm(m.n());
  for (int i = 0; i < m.n(); ++i) {  // parents first: the in-house CMs at zero coordinates
    const Body& b = m.bodies[i];
    point[i] = (b.parent < 0 ? Vec3::Zero() : cm[b.parent]) + b.joint.in_parent;
    cm[i] = point[i] - b.joint.in_body;
  }
  std::vector<BodyDef> defs(m.n());
  for (int i = 0; i < m.n(); ++i) {
    const Body& b = m.bodies[i];
    BodyDef& d = defs[b.file_index];
    d = {b.name, b.parent < 0 ? -1 : m.bodies[b.parent].file_index, mj[i].m, mj[i].J, b.joint};
    d.joint.in_parent = point[i] - (b.parent < 0 ? Vec3::Zero() : mj[b.parent].c);
    d.joint.in_body = point[i] - mj[i].c;
  }
  return buildModel(m.name, m.gravity, defs);
}

// One engine at the states of a crosscheck, and its "<name>-mass" twin
// where it compiles its own masses.
struct Checked {
  std::string name;
  std::unique_ptr<EngineModel> model;
  std::optional<Model> with_mass;
};

// max|udot - in.udot| / in.udot_scale (1 in place of a zero scale).
double differenceIn(const Eigen::VectorXd& udot, const Inhouse& in) {
  return (udot - in.udot).cwiseAbs().maxCoeff() / (in.udot_scale > 0 ? in.udot_scale : 1.0);
}

void compare(const Model& m, EngineModel& engine, const std::string& name, int k, const Eigen::VectorXd& q,
             const Eigen::VectorXd& u, CrossCheck& c) {
  const Inhouse in = inhouseAt(m, q, u);
  const EngineEquations e = engine.at(q, u);
  if (m.isMechanism() && engineCode(parseEngine(name)).mechanism_state) {  // its B and u' are the tree's: A alone
    c.rows.push_back({k, name, relativeDifference(e.A, in.A), 0, 0, false, true});
    return;
  }
  c.rows.push_back({k, name, relativeDifference(e.A, in.A), relativeDifference(e.B, in.B), differenceIn(e.udot, in)});
}

std::vector<Checked> checkedEngines(const Scene& scene, const UrdfOptions& urdf, CrossCheck& c) {
  std::vector<Checked> out;
  for (Engine e : otherEngines()) {
    if (!engineCode(e).model) continue;
    // A mechanism only where the row maps its loops, point springs and drives: never as the tree it would be without them.
    if (const std::string why = mechanismRefusal(e, scene.model); !why.empty()) {
      c.skipped.push_back(std::string(engineName(e)) + ": " + why);
      continue;
    }
    try {
      Checked k{engineName(e), engineModel(e, scene, urdf, c.notes), std::nullopt};
      const std::vector<CompiledMass> mass = k.model->compiledMass();
      if (!mass.empty() && !scene.model.isMechanism()) k.with_mass = withMass(scene.model, mass);  // withMass builds the tree alone
      if (const auto dependence = engineCode(e).dependence; dependence && dependence(scene.model).any()) {
        c.dependent[k.name] = dependence(scene.model);
        if (k.with_mass) c.dependent[massRowName(k.name)] = c.dependent[k.name];
      }
      out.push_back(std::move(k));
    } catch (const std::exception& ex) {
      c.skipped.push_back(std::string(engineName(e)) + ": " + ex.what());
    }
  }
  return out;
}

}  // namespace

double relativeDifference(const Eigen::MatrixXd& x, const Eigen::MatrixXd& y) {
  const double scale = y.cwiseAbs().maxCoeff();
  return (x - y).cwiseAbs().maxCoeff() / (scale > 0 ? scale : 1.0);
}

std::string massRowName(const std::string& engine) { return engine + "-mass"; }

namespace {

// A plugin's u' at every state (in a child process) against the in-house u' and each engine's.
void comparePlugin(const Model& m, Method plugin, std::vector<Checked>& engines, const std::vector<Eigen::VectorXd>& qs,
                   const std::vector<Eigen::VectorXd>& us, CrossCheck& c) {
  const std::vector<Eigen::VectorXd> udot = pluginUdots(plugin, m, qs, us);
  const std::string name = methodName(plugin);
  for (const Checked& e : engines)  // against an engine's u', the engine's dependence
    if (const auto d = c.dependent.find(e.name); d != c.dependent.end() && !d->second.udot.empty())
      c.dependent[name + "/" + e.name] = {"", "", d->second.udot};
  for (size_t k = 0; k < qs.size(); ++k) {
    const Inhouse in = inhouseAt(m, qs[k], us[k]);  // once per state, for every row below
    c.rows.push_back({static_cast<int>(k), name, 0, 0, differenceIn(udot[k], in), true});
    for (Checked& e : engines) {
      if (m.isMechanism() && engineCode(parseEngine(e.name)).mechanism_state) continue;  // its u' of a mechanism is not exposed
      const Eigen::VectorXd theirs = e.model->at(qs[k], us[k]).udot;
      // On a mechanism relative to the in-house scale (the larger of the constrained and the free u', inhouseAt's reason).
      const double diff = m.isMechanism() ? differenceIn(udot[k], {{}, {}, theirs, in.udot_scale}) : relativeDifference(udot[k], theirs);
      c.rows.push_back({static_cast<int>(k), name + "/" + e.name, 0, 0, diff, true});
    }
  }
}

}  // namespace

// A mechanism's consistent states (consistentState).
constexpr double kConsistentTol = 1e-12;   // m or rad: the assembly's own tolerance
constexpr int kProjectionSteps = 50;       // Gauss-Newton steps per draw (io's kAssembleIterations)
constexpr int kDraws = 200;                // draws per state before giving up

void consistentState(const Model& m, std::mt19937& rng, Eigen::VectorXd& q, Eigen::VectorXd& u) {
  Workspace ws(m);
  LoopProjector project(m);
  for (int draw = 0; draw < kDraws; ++draw) {
    randomState(m, rng, q, u);
    if (!project.positions(m, ws, q.data(), u.data(), kConsistentTol, kProjectionSteps).converged) continue;
    project.velocities(u.data());
    return;
  }
  throw std::runtime_error("no consistent state found in " + std::to_string(kDraws) +
                           " random draws projected onto the loops (every projection failed to converge)");
}

CrossCheck crossCheck(const Scene& scene, const UrdfOptions& urdf, int states, unsigned seed, const std::vector<Method>& plugins) {
  const Model& m = scene.model;
  CrossCheck c;
  if (m.isMechanism())
    c.notes.push_back("a mechanism: A and B are the tree's; u' is the constrained one (docs/theory.md eq. (M7)), at the "
                      "initial state and at random states projected onto the loops");
  std::vector<Checked> engines = checkedEngines(scene, urdf, c);
  std::mt19937 rng(seed);
  Eigen::VectorXd q = m.q0(), u = m.u0();
  std::vector<Eigen::VectorXd> qs, us;
  for (int k = 0; k <= states; ++k) {
    if (k > 0 && m.loops.empty()) randomState(m, rng, q, u);
    if (k > 0 && !m.loops.empty()) consistentState(m, rng, q, u);
    qs.push_back(q), us.push_back(u);
    for (Checked& e : engines) {
      compare(m, *e.model, e.name, k, q, u, c);
      if (e.with_mass) compare(*e.with_mass, *e.model, massRowName(e.name), k, q, u, c);
    }
  }
  for (Method p : plugins) comparePlugin(m, p, engines, qs, us, c);
  return c;
}

}  // namespace em
