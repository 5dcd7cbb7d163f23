#include "solver/registry.hpp"

#include <stdexcept>


namespace em {

// Each in-house method's code, defined in its own file (solver/method_*.cpp).
MethodFactory makeClassical, makeArticulated, makeEigen, makeEigenBlock;

namespace {

// Options several rows share, written once.
const MethodParam kRefine = {"refine", 0, 0, 10, true,
                             "Eigenfactor methods: residual corrections per evaluation, u' += C^T Lambda^-1 C (B - A u') "
                             "(docs/theory.md §8, eq. (R)); 0 = the paper's u'"};
const MethodParam kBlockGap = {"block_gap", 3e-2, 0, 1, false,
                               "eigen-block: eigenvalues closer than this times the largest share a block (delta; "
                               "docs/theory.md §8)"};

}  // namespace

const std::vector<EngineInfo>& engineTable() {
  static const std::vector<EngineInfo> table = {
      {Engine::InHouse, "inhouse", Integrator::RK4, Integrator::RK8PD},
      {Engine::Simbody, "simbody", Integrator::RKMerson, Integrator::RKMerson},
      {Engine::Mujoco, "mujoco", Integrator::RK4, Integrator::RK4},  // MuJoCo 2.2 has no adaptive scheme
  };
  return table;
}

const std::vector<MethodInfo>& methodTable() {
  static const std::vector<MethodInfo> table = {
      {Method::Classical, "classical", Engine::InHouse, Correction::None, ExtraState::None, false, makeClassical, {},
       "Cholesky of A every evaluation (paper method a)"},
      {Method::Articulated, "articulated", Engine::InHouse, Correction::None, ExtraState::None, false, makeArticulated, {},
       "Featherstone's articulated-body recursion: u' in O(n) without forming A (not in the paper)"},
      {Method::Eigen, "eigen", Engine::InHouse, Correction::None, ExtraState::CLambda, true, makeEigen, {kRefine},
       "Junkins-Schaub: C and lambda integrated, u' = C^T Lambda^-1 C B (paper method b)"},
      {Method::EigenJacobi, "eigen-jacobi", Engine::InHouse, Correction::Jacobi, ExtraState::CLambda, true, makeEigen,
       {kRefine}, "eigen plus a Jacobi re-diagonalization after every step (paper method c)"},
      {Method::EigenJacobiOrth, "eigen-jacobi-orth", Engine::InHouse, Correction::OrthonormalizeJacobi,
       ExtraState::CLambda, true, makeEigen, {kRefine}, "eigen-jacobi that also re-orthonormalizes C (not in the paper)"},
      {Method::EigenBlock, "eigen-block", Engine::InHouse, Correction::None, ExtraState::CD, true, makeEigenBlock,
       {kRefine, kBlockGap},
       "A = C^T D C with D block diagonal over eigenvalue clusters: survives near-crossings (not in the paper)"},
      {Method::EigenBlockJacobi, "eigen-block-jacobi", Engine::InHouse, Correction::Jacobi, ExtraState::CD, true,
       makeEigenBlock, {kRefine, kBlockGap}, "eigen-block plus the paper's Jacobi correction after every step"},
      {Method::Simbody, "simbody", Engine::Simbody, Correction::None, ExtraState::None, false, nullptr, {},
       "Simbody's own O(n) recursive dynamics: the independent engine"},
      {Method::Mujoco, "mujoco", Engine::Mujoco, Correction::None, ExtraState::None, false, nullptr, {},
       "MuJoCo 2.2's own dynamics (CRB mass matrix, sparse LTDL): a second independent engine, fixed step"},
  };
  return table;
}

const std::vector<IntegratorInfo>& integratorTable() {
  static const std::vector<IntegratorInfo> table = {
      {Integrator::RK4, "rk4", {Engine::InHouse, Engine::Mujoco}, true, rk4Step, nullptr,
       "classical four-stage Runge-Kutta, fixed step (in-house: hand-written; mujoco: MuJoCo's RK4, the same tableau)"},
      {Integrator::RKF45, "rkf45", {Engine::InHouse}, false, nullptr, &gsl_odeiv2_step_rkf45,
       "GSL Runge-Kutta-Fehlberg (4, 5), adaptive"},
      {Integrator::RK8PD, "rk8pd", {Engine::InHouse}, false, nullptr, &gsl_odeiv2_step_rk8pd,
       "GSL Runge-Kutta Prince-Dormand (8, 9), adaptive"},
      {Integrator::BSIMP, "bsimp", {Engine::InHouse}, false, nullptr, &gsl_odeiv2_step_bsimp,
       "GSL implicit Bulirsch-Stoer, adaptive (stiff)"},
      {Integrator::RKMerson, "rkmerson", {Engine::Simbody}, false, nullptr, nullptr, "Simbody Runge-Kutta-Merson, adaptive"},
      {Integrator::RK3, "rk3", {Engine::Simbody}, false, nullptr, nullptr, "Simbody Runge-Kutta 3, adaptive"},
      {Integrator::CPodes, "cpodes", {Engine::Simbody}, false, nullptr, nullptr, "Simbody CPodes (implicit BDF), adaptive"},
      {Integrator::Euler, "euler", {Engine::Mujoco}, true, nullptr, nullptr,
       "MuJoCo's semi-implicit Euler (velocity first, position from the new velocity; damping implicit), fixed step"},
      {Integrator::Implicit, "implicit", {Engine::Mujoco}, true, nullptr, nullptr,
       "MuJoCo's implicit-in-velocity Euler (damping and velocity-dependent forces implicit), fixed step"},
  };
  return table;
}

const std::vector<FailureInfo>& failureTable() {
  static const std::vector<FailureInfo> table = {
      {Failure::None, "none", "the run completed"},
      {Failure::NonFinite, "non-finite", "NaN or Inf in the state or its derivative"},
      {Failure::BlowUp, "blow-up", "a speed beyond the blow-up bound"},
      {Failure::NotPositiveDefinite, "not-positive-definite", "the Cholesky factorization of A (articulated: of a joint's articulated inertia Delta) failed"},
      {Failure::Singular, "singular", "A (articulated: a joint's Delta) numerically singular: cond beyond 1/eps"},
      {Failure::NonPositiveEigenvalue, "eigenvalue-nonpositive", "an integrated eigenvalue of A (or of D) <= 0"},
      {Failure::EigenGap, "eigen-gap", "an eigenvalue gap (or a gap between blocks) below the floor"},
      {Failure::JacobiNotConverged, "jacobi-not-converged", "the Jacobi correction did not converge"},
      {Failure::RefinementDiverged, "refinement-diverged", "a residual correction of u' grew the residual in the H-norm: the eigenfactors no longer approximate A's inverse"},
      {Failure::IntegratorStopped, "integrator-stopped", "the adaptive integrator gave up"},
      {Failure::StepUnderflow, "step-underflow", "the adaptive step collapsed"},
      {Failure::Engine, "engine", "another engine stopped (a Simbody exception, a MuJoCo warning)"},
  };
  return table;
}

namespace {

template <class Row, class Id>
const Row& row(const std::vector<Row>& table, Id id) {
  for (const Row& r : table)
    if (r.id == id) return r;
  throw std::logic_error("registry: an id without a row");
}

template <class Row, class Id>
bool find(const std::vector<Row>& table, const std::string& name, Id& out) {
  for (const Row& r : table)
    if (name == r.name) {
      out = r.id;
      return true;
    }
  return false;
}

template <class Row>
std::vector<std::string> names(const std::vector<Row>& table) {
  std::vector<std::string> n;
  for (const Row& r : table) n.emplace_back(r.name);
  return n;
}

}  // namespace

const EngineInfo& info(Engine e) { return row(engineTable(), e); }
const MethodInfo& info(Method m) { return row(methodTable(), m); }
const IntegratorInfo& info(Integrator i) { return row(integratorTable(), i); }
const char* engineName(Engine e) { return info(e).name; }
const char* methodName(Method m) { return info(m).name; }
const char* integratorName(Integrator i) { return info(i).name; }
const char* failureName(Failure f) { return row(failureTable(), f).name; }

bool findMethod(const std::string& name, Method& out) { return find(methodTable(), name, out); }
bool findIntegrator(const std::string& name, Integrator& out) { return find(integratorTable(), name, out); }

Method parseMethod(const std::string& name) {
  Method m;
  if (!findMethod(name, m)) throw std::invalid_argument("unknown method '" + name + "' (" + joined(methodNames()) + ")");
  return m;
}

Integrator parseIntegrator(const std::string& name) {
  Integrator i;
  if (!findIntegrator(name, i))
    throw std::invalid_argument("unknown integrator '" + name + "' (" + joined(integratorNames()) + ")");
  return i;
}

std::vector<std::string> methodNames() { return names(methodTable()); }
std::vector<std::string> integratorNames() { return names(integratorTable()); }

std::vector<std::string> integratorNames(Engine e) {
  std::vector<std::string> n;
  for (const IntegratorInfo& r : integratorTable())
    if (r.runs(e)) n.emplace_back(r.name);
  return n;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

Integrator defaultIntegrator(Engine e) { return info(e).fixed_default; }
Integrator adaptiveIntegrator(Engine e) { return info(e).adaptive_default; }

int extraStateSize(ExtraState x, int N) {
  switch (x) {
    case ExtraState::None: return 0;
    case ExtraState::CLambda: return N * N + N;
    case ExtraState::CD: return 2 * N * N;
  }
  throw std::logic_error("registry: an extra state without a size");
}

bool IntegratorInfo::runs(Engine e) const {
  for (Engine x : engines)
    if (x == e) return true;
  return false;
}

bool MethodInfo::takes(const std::string& option) const {
  for (const MethodParam& p : params)
    if (option == p.name) return true;
  return false;
}

double MethodInfo::param(const std::string& option, const MethodOptions& o) const {
  for (const MethodParam& p : params)
    if (option == p.name) {
      const auto set = o.params.find(option);
      return set == o.params.end() ? p.fallback : set->second;
    }
  throw std::logic_error(std::string("registry: method ") + name + " has no option " + option);
}

std::vector<MethodParam> methodParams() {
  std::vector<MethodParam> all;
  for (const MethodInfo& m : methodTable())
    for (const MethodParam& p : m.params) {
      bool seen = false;
      for (const MethodParam& q : all) seen = seen || std::string(q.name) == p.name;
      if (!seen) all.push_back(p);
    }
  return all;
}

void requireCompatible(Method method, Integrator integrator) {
  const Engine e = info(method).engine;
  if (!info(integrator).runs(e))
    throw std::invalid_argument("integrator '" + std::string(integratorName(integrator)) + "' is not one of " +
                                methodName(method) + "'s (" + joined(integratorNames(e)) + ")");
}

}  // namespace em
