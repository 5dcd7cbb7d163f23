#include "compare/engines.hpp"
#include "solver/control.hpp"

#include <cmath>
#include <stdexcept>

#include "compare/progress.hpp"
#include "outside/plugin.hpp"
#include "outside/recorded.hpp"
#include "reference/engine.hpp"
#include "solver/dynamics.hpp"
#include "solver/formation.hpp"
#include "solver/integrate.hpp"
#include "solver/mechanism/constrained.hpp"
#include "solver/text.hpp"

namespace em {

RunSpec onGrid(RunSpec spec, const Scene& scene, const Grid& grid) {
  spec.t_end = grid.t_end.value_or(scene.t_end);
  spec.output_dt = grid.output_dt.value_or(scene.output_dt);
  return spec;
}

Method referenceMethod() {
  useEngines();
  return info(referenceEngine()).method;
}

RunSpec defaultReferenceSpec(Method method) {
  RunSpec s;
  s.method = method;
  s.integrator = adaptiveIntegrator(info(method).engine);
  s.tol = kReferenceTol;
  return s;
}

Integrator chosenIntegrator(Engine engine, bool tolerance_given) {
  return tolerance_given ? adaptiveIntegrator(engine) : defaultIntegrator(engine);
}

std::string mechanismRefusal(Engine e, const Model& m) {
  if (!m.isMechanism()) return "";
  const EngineCode& code = engineCode(e);
  if (code.mechanism_refusal) return code.mechanism_refusal(m);
  std::string mapped;  // the rows that map mechanisms, named from the table
  for (Engine other : otherEngines())
    if (engineCode(other).mechanism_refusal) mapped += std::string(", ") + engineName(other);
  return "no mapping of a mechanism's loops, point springs or drives to this engine yet (the in-house methods, ida" + mapped + " run it)";
}

std::string methodRefusal(Method method, const Model& m) {
  const MethodInfo& row = info(method);
  // A u' from outside the formation (an engine's under our integrators, a
  // plugin's, a recorded run's) is a tree's: it knows no point springs or drives.
  if (m.isMechanism() && row.tree_only)
    return "its u' comes from outside the formation and knows no loops, point springs or drives (the in-house methods and ida run a mechanism)";
  if (m.has_control && row.tree_only)
    return "its u' comes from outside the formation and knows no joint controller (the in-house methods and the engines' own steps run one)";
  if (!m.limited.empty() && (row.isolated || row.tree_only))
    return "joint limits are in-house events (docs/theory.md §17) or an engine's own stops: not mapped to this method's u'";
  if (row.engine == Engine::InHouse) return "";
  const EngineCode& code = engineCode(row.engine);
  if (!m.limited.empty() && !code.limits_refusal) return "no mapping of joint limits to this engine's stops yet (the in-house methods run them as exact events)";
  if (!m.limited.empty())
    if (std::string why = code.limits_refusal(m); !why.empty()) return why;
  if (std::string why = mechanismRefusal(row.engine, m); !why.empty()) return why;
  return code.refusal ? code.refusal(m) : "";
}

void requireMethodTakes(Method method, const Model& m) {
  if (const std::string why = methodRefusal(method, m); !why.empty()) throw std::invalid_argument(std::string(methodName(method)) + ": " + why);
}

void requireSettingsTaken(const RunSpec& spec, const Model& m) {
  if (spec.engine() == Engine::InHouse) return;
  if (spec.fixedStep())
    if (const std::string why = controlStepRefusal(m, spec.dt); !why.empty()) throw std::invalid_argument(why);
  const EngineCode& code = engineCode(spec.engine());
  if (!code.settings_refusal) return;
  if (const std::string why = code.settings_refusal(m, spec); !why.empty()) throw std::invalid_argument(why);
}

void requireRunnable(const RunSpec& spec, const Model& m) {
  requireMethodTakes(spec.method, m);
  requireSettingsTaken(spec, m);
  if (spec.engine() == Engine::InHouse && info(spec.method).make) refuseUnrunnable(m, spec);
}

Trajectory runTrajectory(const Model& m, const CheckedRunSpec& checked_spec) {
  const RunSpec& spec = checked_spec;
  requireMethodTakes(spec.method, m);
  requireSettingsTaken(spec, m);
  // Code from outside runs in a child process: what the in-house loop would refuse is refused here first, in one line.
  if (info(spec.method).isolated && spec.engine() == Engine::InHouse) refuseUnrunnable(m, spec);
  ProgressMeter meter(m.name + " " + methodName(spec.method) + "/" + integratorName(spec.integrator), spec.t_end);
  const SampleObserver observe = [&meter](double t) { meter(t); };
  Trajectory tr = recordedRun(spec.method)       ? recordedTrajectory(m, checked_spec)  // a run made elsewhere: nothing runs
                  : info(spec.method).isolated    ? simulateIsolated(m, checked_spec, observe)  // code from outside: in a child process
                  : spec.engine() == Engine::InHouse ? simulate(m, checked_spec, observe)
                                                     : engineCode(spec.engine()).simulate(m, checked_spec, observe);
  recordLoopSamples(m, tr);  // every run's closures at its samples, measured one way
  return tr;
}

std::string engineSceneNote(Engine e, const Model& m) {
  if (e == Engine::InHouse) return "";
  const EngineCode& code = engineCode(e);
  return code.scene_note ? code.scene_note(m) : "";
}

namespace {

// Reorder internal-order results to the source's order and add eigenvalues.
Equations toFileOrder(const Model& m, const Eigen::MatrixXd& A, const Eigen::VectorXd& B, const Eigen::VectorXd& udot,
                      double kinetic, double potential) {
  const std::vector<int> p = m.uFilePermutation();
  Equations e;
  e.nq = m.nq;
  e.nu = m.nu;
  e.A.resize(m.nu, m.nu);
  e.B.resize(m.nu);
  e.udot.resize(m.nu);
  for (int i = 0; i < m.nu; ++i) {
    e.B[i] = B[p[i]];
    e.udot[i] = udot[p[i]];
    for (int j = 0; j < m.nu; ++j) e.A(i, j) = A(p[i], p[j]);
  }
  e.eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(e.A, Eigen::EigenvaluesOnly).eigenvalues();
  e.kinetic = kinetic;
  e.potential = potential;
  return e;
}

}  // namespace

void checkInitialState(const Scene& scene) {
  const Model& m = scene.model;
  const Workspace ws = equationsAtStart(m);
  if (ws.A.allFinite() && (!ws.B.allFinite() || !std::isfinite(ws.energy()))) {
    // A is finite, so masses and levers are: the speeds make B or the kinetic energy overflow.
    Eigen::VectorXd uf;
    m.uToFile(m.u0(), uf);
    Eigen::Index k = 0;
    uf.cwiseAbs().maxCoeff(&k);
    throw std::runtime_error(scene.source.file + ": B or the energy at t = 0 is not finite: an initial speed too large for "
                             "double precision (" + m.uNames()[k] + " = " + gnum(uf[k]) + ")");
  }
  if (!ws.A.allFinite() || !ws.B.allFinite() || !std::isfinite(ws.energy()))
    throw std::runtime_error(scene.source.file + ": the equations at t = 0 are not finite (A, B or the energy): a mass, "
                             "inertia or offset too large for double precision");
  const Eigen::LLT<Eigen::MatrixXd> llt(ws.A);
  if (llt.info() != Eigen::Success)
    throw std::runtime_error(scene.source.file + ": mass matrix A is not positive definite at t = 0" +
                             gimbalLockHint(m, m.q0().data()));
}

Equations inhouseEquations(const Model& m) { return inhouseEquations(m, m.q0(), m.u0()); }

Equations inhouseEquations(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  Workspace ws(m);
  formEquations(m, q.data(), u.data(), ws);
  formEnergies(m, q.data(), ws);
  const Eigen::LLT<Eigen::MatrixXd> llt(ws.A);
  if (llt.info() != Eigen::Success)
    throw std::runtime_error("mass matrix A is not positive definite at this state" + gimbalLockHint(m, q.data()));
  if (m.loops.empty()) return toFileOrder(m, ws.A, ws.B, llt.solve(ws.B), ws.kinetic, ws.potential);
  const ConstrainedEquations c = constrainedAt(m, ws, u.data());
  Equations e = toFileOrder(m, ws.A, ws.B, c.udot, ws.kinetic, ws.potential);
  const std::vector<int> p = m.uFilePermutation();
  e.has_loops = true;
  e.G.resize(m.loop_rows, m.nu);
  for (int j = 0; j < m.nu; ++j) e.G.col(j) = c.loops.G.col(p[j]);
  e.g = c.loops.g;
  e.lambda = c.lambda;
  e.rank = c.rank;
  return e;
}

Equations engineEquations(const Model& m, Engine e) { return engineEquations(m, e, m.q0(), m.u0()); }

Equations engineEquations(const Model& m, Engine e, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  if (e == Engine::InHouse) return inhouseEquations(m, q, u);
  const EngineCode& code = engineCode(e);
  if (!code.model) throw std::invalid_argument(std::string(engineName(e)) + " gives no equations at a state");
  if (m.isMechanism() && !code.mechanism_refusal)
    throw std::invalid_argument(std::string(engineName(e)) + " gives no equations of a mechanism here: its row maps no loops, point springs or drives yet");
  if (m.isMechanism() && code.mechanism_state)  // its equations at a state are the tree's: never printed as the mechanism's
    throw std::invalid_argument(std::string(engineName(e)) + " gives no equations of a mechanism at a state: " + code.mechanism_state);
  if (const std::string why = mechanismRefusal(e, m); !why.empty()) throw std::invalid_argument(std::string(engineName(e)) + ": " + why);
  const EngineEquations x = code.model(m)->at(q, u);
  return toFileOrder(m, x.A, x.B, x.udot, x.kinetic, x.potential);
}

std::vector<Engine> enginesWithEquations() {
  std::vector<Engine> out = {Engine::InHouse};
  for (Engine e : otherEngines())
    if (engineCode(e).model) out.push_back(e);
  return out;
}

}  // namespace em
