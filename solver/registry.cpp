#include "solver/registry.hpp"

#include <cmath>
#include <stdexcept>


namespace em {

// Each in-house method's code, defined in its own file (solver/method_*.cpp).
MethodFactory makeClassical, makeArticulated, makeEigen, makeEigenBlock;

namespace {

// Options several rows share, written once.
const MethodParam kRefine = {"refine", 0, 0, 10, true,
                             "Eigenfactor methods: residual corrections per evaluation, u' += C^T Lambda^-1 C (B - A u') "
                             "(docs/theory.md §8, eq. (R)); 0 = the paper's u'"};
const MethodParam kRefineTol = {"refine_tol", 1e-6, 0, 1, false,
                                "Eigenfactor methods with refine > 0: after the last correction the relative residual "
                                "sqrt(r^T H r / B^T H B) must be within this, or the run fails as refinement-not-converged "
                                "(docs/theory.md §8, eq. (R')); it bounds u''s relative error in the A-norm, not in the 2-norm (up to sqrt(cond A) larger)",
                                "refine"};
const MethodParam kBlockGap = {"block_gap", 3e-2, 0, 1, false,
                               "eigen-block: eigenvalues closer than this times the largest share a block (delta; "
                               "docs/theory.md §8)"};

}  // namespace

namespace {

// The tables themselves: built-in rows, then what addEngine and addMethod add.
std::deque<EngineInfo>& engines() {
  static std::deque<EngineInfo> table = [] {
    EngineInfo inhouse;
    inhouse.name = "inhouse";
    inhouse.summary = "the in-house solver (solver/)";
    inhouse.fixed_scheme = "rk4";
    inhouse.adaptive_scheme = "rk8pd";
    inhouse.id = Engine::InHouse;
    inhouse.fixed_default = Integrator::RK4;
    inhouse.adaptive_default = Integrator::RK8PD;
    inhouse.method = Method::Classical;
    return std::deque<EngineInfo>{inhouse};
  }();
  return table;
}

// A built-in method's row: the in-house engine's, owned by eigenmass.
MethodInfo inHouse(Method id, const char* name, MethodFactory* make, const char* colour, const char* summary) {
  MethodInfo r;
  r.id = id;
  r.name = name;
  r.make = make;
  r.colour = colour;
  r.summary = summary;
  r.owner = kInHouseOwner;
  r.formation_udot = true;
  return r;
}

// An eigenfactor method's row: its extra state, its correction and its options.
MethodInfo eigenfactor(MethodInfo r, ExtraState extra, Correction correction, std::vector<MethodParam> params) {
  r.eigenfactor = true;
  r.extra = extra;
  r.correction = correction;
  r.params = std::move(params);
  return r;
}

std::deque<MethodInfo>& methods() {
  using M = Method;
  using X = ExtraState;
  using C = Correction;
  static std::deque<MethodInfo> table = {
      inHouse(M::Classical, "classical", makeClassical, "tab:blue", "Cholesky of A every evaluation (paper method a)"),
      inHouse(M::Articulated, "articulated", makeArticulated, "tab:cyan",
              "Featherstone's articulated-body recursion: u' in O(n) without forming A (not in the paper)"),
      eigenfactor(inHouse(M::Eigen, "eigen", makeEigen, "tab:orange",
                          "Junkins-Schaub: C and lambda integrated, u' = C^T Lambda^-1 C B (paper method b)"),
                  X::CLambda, C::None, {kRefine, kRefineTol}),
      eigenfactor(inHouse(M::EigenJacobi, "eigen-jacobi", makeEigen, "tab:green",
                          "eigen plus a Jacobi re-diagonalization after every step (paper method c)"),
                  X::CLambda, C::Jacobi, {kRefine, kRefineTol}),
      eigenfactor(inHouse(M::EigenJacobiOrth, "eigen-jacobi-orth", makeEigen, "tab:olive",
                          "eigen-jacobi that also re-orthonormalizes C (not in the paper)"),
                  X::CLambda, C::OrthonormalizeJacobi, {kRefine, kRefineTol}),
      eigenfactor(inHouse(M::EigenBlock, "eigen-block", makeEigenBlock, "tab:purple",
                          "A = C^T D C with D block diagonal over eigenvalue clusters: survives near-crossings (not in the paper)"),
                  X::CD, C::None, {kRefine, kRefineTol, kBlockGap}),
      eigenfactor(inHouse(M::EigenBlockJacobi, "eigen-block-jacobi", makeEigenBlock, "tab:brown",
                          "eigen-block plus the paper's Jacobi correction after every step"),
                  X::CD, C::Jacobi, {kRefine, kRefineTol, kBlockGap}),
  };
  return table;
}

std::deque<IntegratorInfo>& integrators() {
  static std::deque<IntegratorInfo> table = {
      {Integrator::RK4, "rk4", {Engine::InHouse}, true, rk4Step, nullptr,
       "classical four-stage Runge-Kutta, fixed step (one tableau: every engine that lists it runs this scheme)", "o"},
      {Integrator::RKF45, "rkf45", {Engine::InHouse}, false, nullptr, &gsl_odeiv2_step_rkf45,
       "GSL Runge-Kutta-Fehlberg (4, 5), adaptive", "s"},
      {Integrator::RK8PD, "rk8pd", {Engine::InHouse}, false, nullptr, &gsl_odeiv2_step_rk8pd,
       "GSL Runge-Kutta Prince-Dormand (8, 9), adaptive", "^"},
      {Integrator::BSIMP, "bsimp", {Engine::InHouse}, false, nullptr, &gsl_odeiv2_step_bsimp,
       "GSL implicit Bulirsch-Stoer, adaptive (stiff)", "D"},
      {Integrator::IDA, "ida", {Engine::InHouse}, false, nullptr, nullptr,
       "SUNDIALS IDA (variable-order BDF) on the stabilized index-2 form of the equations and the loops, adaptive: "
       "the reference of mechanisms (method classical's formation, IDA's own solves)", "*", true},
      {Integrator::Trapezoidal, "trapezoidal", {Engine::InHouse}, true, nullptr, nullptr,
       "the trapezoidal rule, implicit, fixed step, Newton on the index-3 augmented Lagrangian with mass-orthogonal "
       "projections (formulation augmented-lagrangian; on a tree, on A u' = B); q' = u: no ball or free joints "
       "(method classical's formation, its own solves)", "P", false, true},
      {Integrator::CVODE, "cvode", {Engine::InHouse}, false, nullptr, nullptr,
       "SUNDIALS CVODE, variable-order BDF (1 to 5), Newton on a difference-quotient Jacobian, adaptive (stiff), on the "
       "method's own u'; samples interpolated from its steps; no method or formulation that corrects the state between steps",
       "X", false, false, true},
  };
  return table;
}

}  // namespace

const std::deque<EngineInfo>& engineTable() { return engines(); }
const std::deque<MethodInfo>& methodTable() { return methods(); }
const std::deque<IntegratorInfo>& integratorTable() { return integrators(); }

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
      {Failure::RefinementNotConverged, "refinement-not-converged", "the residual corrections of u' shrank the residual, but not within refine_tol: u' is not the solve's"},
      {Failure::Engine, "engine", "another engine stopped (a Simbody exception, a MuJoCo warning)"},
      {Failure::Plugin, "plugin", "a plugin's u' returned an error code, crashed or did not return (its run is in a child process)"},
      {Failure::EndedEarly, "ended-early", "a recorded run's samples end before the comparison's grid does"},
      {Failure::LoopsOpen, "loops-open", "a mechanism's closures opened beyond the loop tolerance, or the projection could not close them (a singular position)"},
  };
  return table;
}

const std::vector<OutcomeInfo>& outcomeTable() {
  static const std::vector<OutcomeInfo> table = {{Outcome::Ok, "ok"}, {Outcome::Wrong, "wrong"}, {Outcome::Failed, "failed"}};
  return table;
}

namespace {

template <class Table, class Id>
const auto& row(const Table& table, Id id) {
  for (const auto& r : table)
    if (r.id == id) return r;
  throw std::logic_error("registry: an id without a row");
}

// Whether a row is listed and found by name: a retired method's is not.
template <class Row>
bool live(const Row&) {
  return true;
}
bool live(const MethodInfo& r) { return !r.retired; }

template <class Table, class Id>
bool find(const Table& table, const std::string& name, Id& out) {
  for (const auto& r : table)
    if (live(r) && name == r.name) {
      out = r.id;
      return true;
    }
  return false;
}

template <class Table>
std::vector<std::string> names(const Table& table) {
  std::vector<std::string> n;
  for (const auto& r : table)
    if (live(r)) n.emplace_back(r.name);
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
const char* outcomeName(Outcome o) { return row(outcomeTable(), o).name; }

bool findMethod(const std::string& name, Method& out) { return find(methodTable(), name, out); }
bool findIntegrator(const std::string& name, Integrator& out) { return find(integratorTable(), name, out); }
bool findEngine(const std::string& name, Engine& out) { return find(engineTable(), name, out); }
bool findOutcome(const std::string& name, Outcome& out) { return find(outcomeTable(), name, out); }
bool findFailure(const std::string& name, Failure& out) { return find(failureTable(), name, out); }

int schemeIndex(Engine e, Integrator i) {
  const EngineInfo& row = info(e);
  for (size_t k = 0; k < row.scheme_rows.size(); ++k)
    if (row.scheme_rows[k] == i) return static_cast<int>(k);
  throw std::logic_error(std::string("registry: ") + row.name + " has no scheme " + integratorName(i));
}

bool hasAdaptiveScheme(Engine e) {
  for (const IntegratorInfo& i : integratorTable())
    if (i.runs(e) && !i.fixed_step) return true;
  return false;
}

std::vector<Engine> otherEngines() {
  std::vector<Engine> e;
  for (const EngineInfo& r : engineTable())
    if (r.id != Engine::InHouse) e.push_back(r.id);
  return e;
}

Engine referenceEngine() {
  for (const EngineInfo& r : engineTable())
    if (r.roles.reference) return r.id;
  return Engine::InHouse;
}

Engine secondEngine() {
  for (const EngineInfo& r : engineTable())
    if (r.roles.second_scheme) return r.id;
  return Engine::InHouse;
}

std::string methodOwner(Method m) {
  const MethodInfo& r = info(m);
  return r.owner ? r.owner : r.name;
}

Engine parseEngine(const std::string& name) {
  Engine e;
  if (!findEngine(name, e)) throw std::invalid_argument("unknown engine '" + name + "' (" + joined(names(engineTable())) + ")");
  return e;
}

namespace {

bool nameTaken(const std::string& name) {
  Method m;
  Engine e;
  return findMethod(name, m) || findEngine(name, e);
}

// The integrator row of another engine's scheme: the row of that name (one
// name, one scheme), now also listing `e`, or a new row.
Integrator schemeRow(const EngineScheme& s, Engine e) {
  Integrator id;
  if (findIntegrator(s.name, id)) {
    IntegratorInfo& r = integrators()[static_cast<size_t>(id)];
    if (r.fixed_step != s.fixed_step) throw std::logic_error(std::string("registry: scheme ") + s.name + " differs");
    r.engines.push_back(e);
    return id;
  }
  id = static_cast<Integrator>(integrators().size());
  integrators().push_back({id, s.name, {e}, s.fixed_step, nullptr, nullptr, s.summary, s.marker});
  return id;
}

}  // namespace

Engine addEngine(EngineInfo row) {
  if (nameTaken(row.name)) throw std::logic_error(std::string("registry: the name ") + row.name + " is taken");
  row.id = static_cast<Engine>(engines().size());
  row.method = static_cast<Method>(methods().size());
  for (const EngineScheme& s : row.schemes) row.scheme_rows.push_back(schemeRow(s, row.id));
  row.fixed_default = parseIntegrator(row.fixed_scheme);
  row.adaptive_default = parseIntegrator(row.adaptive_scheme);
  MethodInfo m;
  m.id = row.method;
  m.name = row.name;
  m.engine = row.id;
  m.summary = row.summary;
  m.colour = row.colour;
  m.owner = row.name;
  m.params = row.params;
  engines().push_back(row);
  methods().push_back(m);
  return row.id;
}

Method addMethod(MethodInfo row) {
  if (nameTaken(row.name)) throw std::invalid_argument(std::string("the method name '") + row.name + "' is taken");
  row.id = static_cast<Method>(methods().size());
  methods().push_back(row);
  return row.id;
}

void retireMethod(Method m) {
  for (MethodInfo& r : methods())
    if (r.id == m) {
      if (r.owner)  // the built-in rows are eigenmass's, an engine's its own: only rows from outside have none
        throw std::logic_error(std::string("registry: ") + r.name + " is a built-in or an engine's method");
      r.retired = true;
      return;
    }
  throw std::logic_error("registry: retireMethod of an id without a row");
}

Integrator addIntegrator(IntegratorInfo row) {
  Integrator taken;
  if (findIntegrator(row.name, taken)) throw std::logic_error(std::string("registry: the scheme ") + row.name + " exists");
  row.id = static_cast<Integrator>(integrators().size());
  integrators().push_back(row);
  return row.id;
}

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

std::string methodColour(Method m) {
  if (const char* c = info(m).colour) return c;
  // Methods added without a colour (plugins, Python functions): matplotlib's
  // second palette, by id, so that the same method has the same colour in every figure.
  static const char* const kPalette[] = {"#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#1b9e77", "#d95f02", "#7570b3"};
  return kPalette[static_cast<size_t>(m) % (sizeof kPalette / sizeof *kPalette)];
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

MethodParam methodParam(const std::string& name) {
  for (const MethodParam& p : methodParams())
    if (name == p.name) return p;
  throw std::logic_error("registry: no row has the option " + name);
}

void requireCompatible(Method method, Integrator integrator) {
  const Engine e = info(method).engine;
  if (!info(integrator).runs(e))
    throw std::invalid_argument("integrator '" + std::string(integratorName(integrator)) + "' is not one of " +
                                methodName(method) + "'s (" + joined(integratorNames(e)) + ")");
}

}  // namespace em
