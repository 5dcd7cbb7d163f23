#pragma once
/// One table per kind of thing (MuJoCo's one enum and one name table): the
/// engines, the methods, the integrators and the failures, with the
/// properties every other part reads instead of comparing names. Adding an
/// in-house method is its enum value, its row here (its options and
/// properties are columns), its own file and its CMake line; adding a
/// fixed-step integrator is its enum value, its row and its step function
/// (solver/steppers.hpp). Another engine, or a method from outside (a
/// plugin, a Python function), is added at run time (addEngine, addMethod):
/// its ids follow the built-in ones, and only its name is ever written down.
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "solver/method_options.hpp"
#include "solver/steppers.hpp"

namespace em {

struct Model;
class MethodImpl;

/// Who runs a method or an integrator: the in-house code, or another engine
/// (ids from 1 on, in the order addEngine was told of them).
enum class Engine : int { InHouse };

/// The in-house methods; an engine's method and a method from outside
/// (addMethod) take the ids after them.
enum class Method : int { Classical, Articulated, Eigen, EigenJacobi, EigenJacobiOrth, EigenBlock, EigenBlockJacobi };

/// The in-house integrators; another engine's own schemes take the ids after them.
enum class Integrator : int { RK4, RKF45, RK8PD, BSIMP, IDA, Trapezoidal, CVODE };

/// Another engine's integrator, as its row names it: a name already in the
/// table (e.g. rk4: the same tableau) is that row, which then also lists the engine.
struct EngineScheme {
  const char* name;
  bool fixed_step;
  const char* summary;
  const char* marker;  ///< in figures (a shared scheme keeps its row's)
};

/// What a comparison takes an engine for when nothing else is asked, stated
/// on its row and nowhere else: the reference of scenes without loops (its
/// adaptive scheme at kReferenceTol), and the second engine beside it.
struct EngineRoles {
  bool reference = false;               ///< the default reference
  const char* second_scheme = nullptr;  ///< the second engine's scheme (nullptr: not the second engine)
  double second_dt = 0;                 ///< and its step (finer where the output step is)
};

/// An engine's own code: how it runs, what it gives at a state, what it says
/// of itself (reference/engine.hpp). The registry never looks inside it.
struct EngineCode;

/// One of a method's own options, a column of its row: the plan key and the
/// report key are `name`, the CLI option is `--` + name with '_' as '-'.
struct MethodParam {
  const char* name;
  double fallback;   ///< the value when none is set
  double min, max;   ///< allowed: [min, max] for whole numbers, (min, max] otherwise
  bool whole;        ///< a whole number (reports and plan keys write it as one)
  const char* help;  ///< one line: --help and docs
  /// Another option this one is read under, only when that one is > 0
  /// (refine_tol under refine); nullptr: always read. Given where it is not
  /// read, it is refused (the CLI, plans).
  const char* read_when = nullptr;
  /// Read only on a scene with loops (an engine's closures' stabilization,
  /// MuJoCo's solref): given for a tree, it is refused.
  bool loops_only = false;
  /// Read only on a scene with joint limits (an engine's stops' softness,
  /// MuJoCo's solreflimit): given for a scene without, it is refused.
  bool limits_only = false;
};

/// An engine's row, found by its id (info(Engine)). Its fields are named
/// where it is written (reference/<name>.cpp); addEngine sets the last three.
struct EngineInfo {
  const char* name = nullptr;
  const char* summary = nullptr;       ///< its method's one line (--help, docs)
  /// Its integrators (rk4: the in-house tableau). A scheme's position here is
  /// its id (schemeIndex): the engine's code names its schemes by an enum in this order.
  std::vector<EngineScheme> schemes;
  const char* fixed_scheme = nullptr;  ///< what it runs when nothing is asked
  const char* adaptive_scheme = nullptr;  ///< a tolerance alone, and as a reference
  double max_tol = HUGE_VAL;           ///< a tolerance must be below it (Simbody asserts on an accuracy >= 1)
  const char* colour = nullptr;        ///< its method's colour in every figure (matplotlib name)
  EngineRoles roles;
  /// Its method's own options (how soft or stabilized its closures are), with
  /// the engine's defaults: CLI options, plan keys, and every report writes them as run.
  std::vector<MethodParam> params;
  const EngineCode* code = nullptr;    ///< its code (nullptr for the in-house engine)
  // Set by addEngine:
  Engine id = Engine::InHouse;
  Integrator fixed_default = Integrator::RK4;     ///< fixed_scheme's row
  Integrator adaptive_default = Integrator::RK4;  ///< adaptive_scheme's row
  Method method = Method::Classical;              ///< the method it runs (in-house: the reference's, classical)
  std::vector<Integrator> scheme_rows;            ///< each scheme's integrator row, in schemes' order
};

/// The owner of the in-house methods' routes (MethodInfo::owner): the engine
/// study's and the benchmark's "eigenmass", which every table compares against.
inline constexpr const char* kInHouseOwner = "eigenmass";

/// Tolerance of a reference run when none is asked (with the engine's adaptive default).
constexpr double kReferenceTol = 1e-10;

/// What an in-house method does to its extra state after every accepted step.
enum class Correction { None, Jacobi, OrthonormalizeJacobi };

/// The extra state a method integrates beside (q, u) (docs/theory.md §7–8).
enum class ExtraState {
  None,     ///< nothing
  CLambda,  ///< C (N*N, row-major, rows = eigenvectors), then lambda (N)
  CD,       ///< C (N*N, row-major), then D (N*N, column-major, block diagonal)
};
/// Entries of that extra state for N = nu.
int extraStateSize(ExtraState x, int N);


struct MethodInfo;
/// Builds an in-house method's own code for one model (defined in the method's own file).
using MethodFactory = std::unique_ptr<MethodImpl>(const Model&, const MethodInfo&, const MethodOptions&);

/// A method's row. Its fields are named where it is written (the built-in
/// rows, an engine's, a plugin's); addMethod sets its id.
struct MethodInfo {
  Method id = Method::Classical;
  const char* name = nullptr;
  Engine engine = Engine::InHouse;
  Correction correction = Correction::None;
  ExtraState extra = ExtraState::None;  ///< what it integrates beside (q, u)
  bool eigenfactor = false;             ///< integrates a factorization of A: drift diagnostics
  MethodFactory* make = nullptr;        ///< in-house methods only (nullptr for another engine's)
  std::vector<MethodParam> params;      ///< its own options (values in MethodOptions::params)
  const char* summary = nullptr;        ///< one line: --help and docs
  const char* colour = nullptr;         ///< its colour in every figure (matplotlib name); nullptr: methodColour's palette
  /// Its runs go through a child process (code from outside that may crash
  /// or hang: a plugin's; compare/engines.cpp's runTrajectory).
  bool isolated = false;
  /// Whose route it is in the engine study: kInHouseOwner for the in-house
  /// methods, an engine's name for its method; nullptr: its own name (an
  /// engine's u' under the in-house integrators, a plugin).
  const char* owner = nullptr;
  /// Its u' is the formation's A^-1 B (a built-in method): an integrator that
  /// integrates A and B itself (ida, trapezoidal) runs what this method
  /// would. False for a u' from outside (a plugin's, a Python function's, an
  /// engine's): such an integrator would silently run classical in its place,
  /// so the pair is refused (refuseUnrunnable).
  bool formation_udot = false;
  /// Its u' comes from outside the formation (an engine's under the in-house
  /// integrators, a plugin's, a Python function's, a recorded run): a tree's,
  /// so a mechanism is refused for it (compare/engines.hpp's methodRefusal).
  bool tree_only = false;
  /// An engine's u' under the in-house integrators: that engine's name. Its
  /// runs at tight tolerances measure how far the engine's own dynamics (its
  /// model, e.g. MuJoCo's rounded inertias) lie from the exact motion: the
  /// engine study's floor for that engine's routes. nullptr otherwise.
  const char* dynamics_of = nullptr;
  /// Retired (retireMethod): its name is no longer found, listed or taken;
  /// its id still reads its row.
  bool retired = false;

  /// Whether the row has the option `name`.
  bool takes(const std::string& name) const;
  /// The value of its option `name` in `o` (the fallback when unset);
  /// throws std::logic_error when the row has no such option.
  double param(const std::string& name, const MethodOptions& o) const;
};

/// An integrator row. One name means one scheme: rk4 is the in-house rk4 and
/// MuJoCo's RK4 (the same tableau), so it lists both engines.
struct IntegratorInfo {
  Integrator id;
  const char* name;
  std::vector<Engine> engines;  ///< who runs it
  bool fixed_step;  ///< a step dt (else a tolerance: adaptive)
  FixedStep step;   ///< in-house fixed-step schemes: one step of exactly h
  GslStepper gsl;   ///< in-house adaptive schemes: GSL's stepper
  const char* summary;
  const char* marker = nullptr;  ///< its marker in every figure (matplotlib); nullptr: "."
  /// A DAE solver (IDA) that integrates the formation's A and B and the loops
  /// itself (solver/ida.hpp): it runs with a method that has no extra state.
  bool dae = false;
  /// The trapezoidal rule of the index-3 augmented Lagrangian
  /// (solver/augmented_lagrangian.hpp): it steps A, B and the loops itself, a
  /// fixed step dt, with a method that has no extra state.
  bool augmented_lagrangian = false;
  /// A multistep solver (CVODE's BDF, solver/ode_bdf.hpp) that steps the
  /// method's y' itself: its history forbids a state corrected between steps.
  bool multistep = false;
  /// Integrates the formation's A and B itself (ida, trapezoidal): no step function, no method's state.
  bool stepsItself() const { return dae || augmented_lagrangian; }
  /// Whether code of ours steps it (a recorded run's row has none).
  bool stepped() const { return stepsItself() || multistep || (fixed_step ? step != nullptr : gsl != nullptr); }
  bool runs(Engine e) const;
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
  RefinementDiverged,     ///< a residual correction of u' grew the residual (the refine option)
  RefinementNotConverged, ///< the last correction left the relative residual above refine_tol
  IntegratorStopped,      ///< the adaptive integrator gave up
  StepUnderflow,          ///< the adaptive step collapsed below 1e-14 t
  Engine,                 ///< another engine (Simbody, MuJoCo, ...) threw or warned
  Plugin,                 ///< a plugin's u' returned an error, crashed or hung (outside/plugin.hpp)
  EndedEarly,             ///< a recorded run's samples end before the grid does (outside/recorded.hpp)
  LoopsOpen,              ///< a mechanism's closures opened beyond MethodOptions' loop_tol (or the projection did not close them)
};

/// How a run came out, as every report, CSV and table writes it: completed
/// (ok), completed but beyond compare's kWrongRad of the reference before its
/// horizon (wrong: only a comparison can tell), or stopped (failed). A run on
/// its own is ok or failed (RunEnd::status()).
enum class Outcome { Ok, Wrong, Failed };

struct OutcomeInfo {
  Outcome id;
  const char* name;
};

struct FailureInfo {
  Failure id;
  const char* name;
  const char* summary;
};

/// The tables, in the order every listing uses (built-in rows first, then
/// what was added, in order; a row's address never changes).
const std::deque<EngineInfo>& engineTable();
const std::deque<MethodInfo>& methodTable();
const std::deque<IntegratorInfo>& integratorTable();
const std::vector<FailureInfo>& failureTable();
const std::vector<OutcomeInfo>& outcomeTable();

/// Another engine, its method (named as the engine) and its schemes, added
/// to the tables; its row's fixed_scheme and adaptive_scheme name two of its
/// schemes. Throws std::logic_error for a name already taken. Not thread-safe:
/// add before any run starts.
Engine addEngine(EngineInfo row);
/// A method from outside (a plugin, a Python function) run by the in-house
/// integrators through `make`; its row's id is set here. Throws
/// std::invalid_argument for a name already taken.
Method addMethod(MethodInfo row);

/// A method from outside that lived for one call (the Python module's runs,
/// plugins and functions): its name is freed, and it leaves the lists
/// (methodNames, findMethod, CompareOptions' defaults). Built-in and engine
/// rows are never retired (std::logic_error).
void retireMethod(Method m);

/// A scheme none of the engines runs (a recorded run's "recorded": samples
/// read from a file); its row's id is set here. Throws std::logic_error for a
/// name already taken.
Integrator addIntegrator(IntegratorInfo row);

const EngineInfo& info(Engine e);
const MethodInfo& info(Method m);
const IntegratorInfo& info(Integrator i);
const char* engineName(Engine e);
const char* methodName(Method m);
const char* integratorName(Integrator i);
const char* failureName(Failure f);
const char* outcomeName(Outcome o);

/// The method, integrator or engine of that name; throws std::invalid_argument
/// naming every known one ("unknown method 'x' (classical, ...)").
Method parseMethod(const std::string& name);
Integrator parseIntegrator(const std::string& name);
Engine parseEngine(const std::string& name);
/// The same without throwing.
bool findMethod(const std::string& name, Method& out);
bool findIntegrator(const std::string& name, Integrator& out);
bool findEngine(const std::string& name, Engine& out);
bool findOutcome(const std::string& name, Outcome& out);
bool findFailure(const std::string& name, Failure& out);
/// Which of engine `e`'s schemes `i` is: its position in e's row's schemes,
/// the id an engine's own code compares (never the scheme's name). Throws
/// std::logic_error where `e` does not run `i`.
int schemeIndex(Engine e, Integrator i);
/// Whether engine `e` runs a scheme that takes a tolerance.
bool hasAdaptiveScheme(Engine e);
/// Every engine but the in-house code, in table order.
std::vector<Engine> otherEngines();
/// The engine whose row says it is the default reference (EngineRoles::reference),
/// and the one that is the second engine; the in-house engine where no row says so.
Engine referenceEngine();
Engine secondEngine();
/// Whose route a method is in the engine study (MethodInfo::owner).
std::string methodOwner(Method m);

/// Names in table order, optionally of one engine only (CLI validators, help).
std::vector<std::string> methodNames();
std::vector<std::string> integratorNames();
std::vector<std::string> integratorNames(Engine e);
/// Every option any method takes, once each, in table order (CLI, plans).
std::vector<MethodParam> methodParams();
/// The option of that name (a row's read_when names one); std::logic_error when no row has it.
MethodParam methodParam(const std::string& name);
/// A method's colour in figures: its row's, else one of a fixed palette by its id.
std::string methodColour(Method m);

/// "a, b, c": the names joined for messages and help texts.
std::string joined(const std::vector<std::string>& names);

/// The integrator an engine runs when none is asked for (EngineInfo::fixed_default).
Integrator defaultIntegrator(Engine e);
/// Its adaptive one (EngineInfo::adaptive_default): a tolerance given alone, reference runs.
Integrator adaptiveIntegrator(Engine e);
/// An integrator that `method`'s engine runs; throws std::invalid_argument otherwise.
void requireCompatible(Method method, Integrator integrator);

}  // namespace em
