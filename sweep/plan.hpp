#pragma once
/// A sweep plan (`eigenmass-plan/1`, docs/sweep.md): scenes x methods x
/// integrators x steps or tolerances, the horizon, the reference and the
/// number of repeats; and the cases it expands to, each with a stable name
/// that is also its result file's.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "compare/engines.hpp"
#include "io/scene_json.hpp"
#include "io/urdf.hpp"
#include "sweep/ensemble.hpp"

namespace em {

/// One of a line's "tuning" sets: values of its methods' own options (the
/// registry rows' params, the plan's top-level keys) and of the augmented
/// Lagrangian's "al_penalty_ratio". Each set is a route of its own, named by
/// it, so that every owner runs at its best settings beside its defaults
/// (issue 76: MuJoCo's solref, ODE's ERP and CFM, ...).
struct Tuning {
  std::vector<std::pair<std::string, double>> values;  ///< key and value, in the keys' order
  /// "mujoco_solref_damping=1 mujoco_solref_time=0.005" ("" for none): the route's name and the records' (no comma: a CSV cell).
  std::string label() const;
  /// The case name's part: "mujoco_solref_damping-1.mujoco_solref_time-0.005".
  std::string tag() const;
  void applyTo(MethodOptions& o) const;
};
/// The tuning key of the augmented Lagrangian's penalty ratio (LoopOptions::penalty_ratio).
constexpr const char* kPenaltyRatioKey = "al_penalty_ratio";

/// One line of a plan: these methods under one integrator at each setting.
struct PlanLine {
  std::vector<Method> methods;
  /// "formulations": each method under each of these on a scene with loops
  /// (a case each, named with it); on a tree, or when empty, the plan's one.
  std::vector<Formulation> formulations;
  Integrator integrator = Integrator::RK4;
  std::vector<double> settings;  ///< dt (fixed-step integrators) or tolerances
  /// "tuning": each method at each setting once per set (empty: once, at the plan's options).
  std::vector<Tuning> tunings;
};

/// The tables a plan's merged results carry (docs/sweep.md).
enum class PlanTable { WorkPrecision, CostVsSize, Runs, Trajectories, EngineStudy, Benchmark };
const char* planTableName(PlanTable t);

/// A scene's start displaced before any case runs: sigma N(0, 1) on every
/// coordinate and speed (solver/perturb.hpp's draw, from `seed`). For a scene
/// at rest on an unstable equilibrium (a URDF starts at q = 0: the Allegro
/// hand), whose runs would otherwise measure round-off amplified by it.
struct StartOffset {
  double q = 0, u = 0;     ///< sigma: rad (m), rad/s (m/s)
  std::uint64_t seed = 0;
};

/// A scene of a plan: an entry of `scenes`, a path or {"file", and a URDF's import options}.
struct PlanScene {
  std::string file;  ///< resolved against the plan's folder
  UrdfOptions urdf;  ///< balance_inertia, lock_joint, floating_base (URDF only)
  bool has_loops = false;                 ///< read from the scene when the plan is loaded
  std::optional<BenchmarkSpec> benchmark; ///< the scene's "benchmark" (the benchmark table reads it)
  std::optional<StartOffset> start_offset; ///< "start_offset": every case starts there (refused on a scene with loops)
  /// Methods that cannot run this scene, and why (compare/engines.hpp's
  /// methodRefusal: an engine's u' under our integrators on a mechanism, a
  /// joint kind an engine lacks): a line's cases of them are left out on it,
  /// and the tables say so (leftOutLines). Read when the plan is loaded.
  std::map<std::string, std::string> refusals;
  std::string name;  ///< "name": the scene's name in the plan where one file appears twice (other starts), else ""
  std::string stem() const;  ///< its name, else the file's stem: it names the cases
};

struct Plan {
  std::string name, description, file;
  std::vector<PlanScene> scenes;
  double t_end = 5, output_dt = 0.01;
  int repeats = 3;                  ///< timing: median of this many runs (>= 3)
  std::optional<RunSpec> reference;        ///< errors against it (absent: cost only)
  std::optional<RunSpec> reference_check;  ///< the reference's own check (another engine)
  std::vector<PlanLine> lines;
  std::vector<PlanTable> tables;
  MethodOptions options;  ///< of every run (the plan's "max_steps" and the methods' options)
  std::optional<Ensemble> ensemble;  ///< members of every scene (absent: the scene alone)
  std::vector<Method> runs;          ///< recorded runs of the plan's one scene ("runs"; outside/recorded.hpp), a case each

  bool hasTable(PlanTable t) const;
};

/// One line per scene and reason where a line's methods cannot run a scene
/// (PlanScene::refusals), naming the methods and how many cases are left
/// out; "" where none is.
std::string leftOutLines(const Plan& p);

/// Read and check a plan. Throws one line naming the file and the key
/// ("plan.json: lines[0].dt[2]: must be a finite number > 0").
Plan loadPlan(const std::string& path);
/// The same of a plan's text that is to be written at `path` (relative files
/// resolve from there), its errors prefixed by `named` instead of the path.
Plan parsePlan(const std::string& text, const std::string& path, const std::string& named);

/// What a case is: its case file's and the merged CSV's "role" (caseRoleName).
enum class CaseRole { Reference, Check, Run };
/// "reference", "check", "run": the name every file writes.
const char* caseRoleName(CaseRole r);
/// The role of that name; false for none.
bool findCaseRole(const std::string& name, CaseRole& out);

/// One case: a scene and a run of one method, or the scene's reference or its check.
struct SweepCase {
  CaseRole role = CaseRole::Run;
  size_t scene = 0;  ///< index into Plan::scenes
  std::string scene_name;  ///< the scene file's stem (unique within a plan)
  int member = 0;          ///< ensemble member (0: the scene itself)
  CheckedRunSpec spec;     ///< on the plan's grid, checked when the case is made (a plan that loaded runs)
  std::string name;        ///< "pendulum5.classical.rk4.1e-2" ("pendulum5.m007.classical..." in an ensemble): result file stem, --case argument
  bool formulation_named = false;  ///< a line's "formulations" on a scene with loops: spec.options.loops.formulation names the case
  std::string tuning;  ///< its line's tuning set (Tuning::label), applied to spec.options; "" for none
};

/// Every case of a plan, references and checks first (in scene and member
/// order), then the runs in plan order: scene, member, line, method, setting.
std::vector<SweepCase> planCases(const Plan& plan);

/// The reference case of `c`'s scene and member (the plan has a reference),
/// built directly: as planCases lists it, without listing every case.
SweepCase referenceCaseOf(const Plan& plan, const SweepCase& c);

}  // namespace em
