#include "solver/registry.hpp"

#include <stdexcept>

#include "solver/formulation.hpp"

namespace em {

const std::vector<MethodInfo>& methodTable() {
  static const std::vector<MethodInfo> table = {
      {Method::Classical, "classical", Engine::InHouse, Correction::None, false, makeClassical,
       "Cholesky of A every evaluation (paper method a)"},
      {Method::Eigen, "eigen", Engine::InHouse, Correction::None, true, makeEigenfactor,
       "Junkins-Schaub: C and lambda integrated, u' = C^T Lambda^-1 C B (paper method b)"},
      {Method::EigenJacobi, "eigen-jacobi", Engine::InHouse, Correction::Jacobi, true, makeEigenfactor,
       "eigen plus a Jacobi re-diagonalization after every step (paper method c)"},
      {Method::EigenJacobiOrth, "eigen-jacobi-orth", Engine::InHouse, Correction::OrthonormalizeJacobi, true,
       makeEigenfactor, "eigen-jacobi that also re-orthonormalizes C (not in the paper)"},
      {Method::EigenBlock, "eigen-block", Engine::InHouse, Correction::None, true, makeEigenBlock,
       "A = C^T D C with D block diagonal over eigenvalue clusters: survives near-crossings (not in the paper)"},
      {Method::EigenBlockJacobi, "eigen-block-jacobi", Engine::InHouse, Correction::Jacobi, true, makeEigenBlock,
       "eigen-block plus the paper's Jacobi correction after every step"},
      {Method::Simbody, "simbody", Engine::Simbody, Correction::None, false, nullptr,
       "Simbody's own O(n) recursive dynamics: the independent engine"},
  };
  return table;
}

const std::vector<IntegratorInfo>& integratorTable() {
  static const std::vector<IntegratorInfo> table = {
      {Integrator::RK4, "rk4", Engine::InHouse, true, "classical four-stage Runge-Kutta, fixed step (hand-written)"},
      {Integrator::RKF45, "rkf45", Engine::InHouse, false, "GSL Runge-Kutta-Fehlberg (4, 5), adaptive"},
      {Integrator::RK8PD, "rk8pd", Engine::InHouse, false, "GSL Runge-Kutta Prince-Dormand (8, 9), adaptive"},
      {Integrator::BSIMP, "bsimp", Engine::InHouse, false, "GSL implicit Bulirsch-Stoer, adaptive (stiff)"},
      {Integrator::RKMerson, "rkmerson", Engine::Simbody, false, "Simbody Runge-Kutta-Merson, adaptive"},
      {Integrator::RK3, "rk3", Engine::Simbody, false, "Simbody Runge-Kutta 3, adaptive"},
      {Integrator::CPodes, "cpodes", Engine::Simbody, false, "Simbody CPodes (implicit BDF), adaptive"},
  };
  return table;
}

const std::vector<FailureInfo>& failureTable() {
  static const std::vector<FailureInfo> table = {
      {Failure::None, "none", "the run completed"},
      {Failure::NonFinite, "non-finite", "NaN or Inf in the state or its derivative"},
      {Failure::BlowUp, "blow-up", "a speed beyond the blow-up bound"},
      {Failure::NotPositiveDefinite, "not-positive-definite", "the Cholesky factorization of A failed"},
      {Failure::Singular, "singular", "A numerically singular: cond(A) beyond 1/eps"},
      {Failure::NonPositiveEigenvalue, "eigenvalue-nonpositive", "an integrated eigenvalue of A (or of D) <= 0"},
      {Failure::EigenGap, "eigen-gap", "an eigenvalue gap (or a gap between blocks) below the floor"},
      {Failure::JacobiNotConverged, "jacobi-not-converged", "the Jacobi correction did not converge"},
      {Failure::RefinementDiverged, "refinement-diverged", "a residual correction of u' grew the residual in the H-norm: the eigenfactors no longer approximate A's inverse"},
      {Failure::IntegratorStopped, "integrator-stopped", "the adaptive integrator gave up"},
      {Failure::StepUnderflow, "step-underflow", "the adaptive step collapsed"},
      {Failure::Engine, "engine", "the other engine (Simbody) stopped with an exception"},
  };
  return table;
}

const char* engineName(Engine e) { return e == Engine::InHouse ? "inhouse" : "simbody"; }

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

const MethodInfo& info(Method m) { return row(methodTable(), m); }
const IntegratorInfo& info(Integrator i) { return row(integratorTable(), i); }
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
    if (r.engine == e) n.emplace_back(r.name);
  return n;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

Integrator defaultIntegrator(Engine e) { return e == Engine::InHouse ? Integrator::RK4 : Integrator::RKMerson; }

void requireCompatible(Method method, Integrator integrator) {
  const Engine e = info(method).engine;
  if (info(integrator).engine != e)
    throw std::invalid_argument("integrator '" + std::string(integratorName(integrator)) + "' is not one of " +
                                methodName(method) + "'s (" + joined(integratorNames(e)) + ")");
}

}  // namespace em
