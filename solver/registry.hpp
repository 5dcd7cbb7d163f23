#pragma once
/// One table per kind of thing (MuJoCo's one enum and one name table): the
/// methods and the integrators with the properties every other part reads
/// instead of comparing names. Adding a method or an integrator is one row
/// here plus its own code (docs/theory.md §8–9).
#include <memory>
#include <string>
#include <vector>

namespace em {

struct Model;
struct MethodOptions;
class Formulation;

/// Who runs a method or an integrator.
enum class Engine { InHouse, Simbody };
const char* engineName(Engine e);

enum class Method { Classical, Eigen, EigenJacobi, EigenJacobiOrth, EigenBlock, EigenBlockJacobi, Simbody };

/// What an in-house method does to its extra state after every accepted step.
enum class Correction { None, Jacobi, OrthonormalizeJacobi };

struct MethodInfo;
/// Builds an in-house method's own code for one model.
using FormulationFactory = std::unique_ptr<Formulation> (*)(const Model&, const MethodInfo&, const MethodOptions&);

struct MethodInfo {
  Method id;
  const char* name;
  Engine engine;
  Correction correction;
  bool eigenfactor;           ///< integrates a factorization of A beside (q, u): drift diagnostics
  FormulationFactory make;    ///< in-house methods only (nullptr for another engine's)
  const char* summary;        ///< one line: --help and docs
};

enum class Integrator { RK4, RKF45, RK8PD, BSIMP, RKMerson, RK3, CPodes };

struct IntegratorInfo {
  Integrator id;
  const char* name;
  Engine engine;
  bool fixed_step;  ///< a step dt (else a tolerance: adaptive)
  const char* summary;
};

/// Why a run stopped: the kind of its numerical failure (reports'
/// `failure.kind`, the extreme gallery's causes); the cause text says the rest.
enum class Failure {
  None,
  NonFinite,              ///< NaN or Inf in the state or its derivative
  BlowUp,                 ///< max |u| beyond MethodOptions::blowup_speed
  NotPositiveDefinite,    ///< Cholesky of A failed
  Singular,               ///< A numerically singular (pivot ratio beyond 1/eps)
  NonPositiveEigenvalue,  ///< an integrated eigenvalue of A (or of D) <= 0
  EigenGap,               ///< an eigenvalue gap (or a gap between blocks) below the floor
  JacobiNotConverged,     ///< the Jacobi correction did not converge
  RefinementDiverged,     ///< a residual correction of u' grew the residual (MethodOptions::refine)
  IntegratorStopped,      ///< the adaptive integrator gave up
  StepUnderflow,          ///< the adaptive step collapsed below 1e-14 t
  Engine,                 ///< another engine (Simbody) threw
};

struct FailureInfo {
  Failure id;
  const char* name;
  const char* summary;
};

/// The tables, in the order every listing uses.
const std::vector<MethodInfo>& methodTable();
const std::vector<IntegratorInfo>& integratorTable();
const std::vector<FailureInfo>& failureTable();

const MethodInfo& info(Method m);
const IntegratorInfo& info(Integrator i);
const char* methodName(Method m);
const char* integratorName(Integrator i);
const char* failureName(Failure f);

/// The method or integrator of that name; throws std::invalid_argument
/// naming every known one ("unknown method 'x' (classical, ...)").
Method parseMethod(const std::string& name);
Integrator parseIntegrator(const std::string& name);
/// The same without throwing.
bool findMethod(const std::string& name, Method& out);
bool findIntegrator(const std::string& name, Integrator& out);

/// Names in table order, optionally of one engine only (CLI validators, help).
std::vector<std::string> methodNames();
std::vector<std::string> integratorNames();
std::vector<std::string> integratorNames(Engine e);
/// "a, b, c": the names joined for messages and help texts.
std::string joined(const std::vector<std::string>& names);

/// The integrator an engine runs when none is asked for (in-house rk4, Simbody RK-Merson).
Integrator defaultIntegrator(Engine e);
/// An integrator that `method`'s engine runs; throws std::invalid_argument otherwise.
void requireCompatible(Method method, Integrator integrator);

}  // namespace em
