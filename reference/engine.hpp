#pragma once
/// The engine seam: every independent engine (Simbody, MuJoCo, ...) is one
/// row of engineRows(), naming what it can do; nothing outside an engine's
/// row and its own files asks which engine it is. Adding an engine is its
/// row (its own file under reference/, listed in reference/table.cpp) and its
/// CMake lines. useEngines() adds every row to the registry
/// (solver/registry.hpp: the engine, its method and its schemes).
#include <memory>
#include <string>
#include <vector>

#include "solver/registry.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// An engine's own equations at one state, the in-house internal order.
struct EngineEquations {
  Eigen::MatrixXd A;         ///< its mass matrix  // (nu x nu)
  Eigen::VectorXd B, udot;   ///< its right-hand side A u' = B, and its u'  // (nu)
  double kinetic = 0, potential = 0;
};

/// What of an engine's equations at a state on one scene is not its own but
/// eigenmass's: a line each for A, B and u' saying what ("" where that entry
/// is the engine's alone). Crosscheck prints such entries as not independent
/// and does not count their agreement: a bug in the code they share is shared.
struct EquationsDependence {
  std::string A, B, udot;
  bool any() const { return !A.empty() || !B.empty() || !udot.empty(); }
};

/// A body's mass properties as an engine compiled them, in the world at the
/// zero configuration: mass, CM, inertia about the CM (world axes).
struct CompiledMass {
  double m = 0;
  Vec3 c = Vec3::Zero();
  Mat3 J = Mat3::Zero();
};

/// An engine's model of one scene, asked for its equations at any state.
class EngineModel {
 public:
  virtual ~EngineModel() = default;
  /// A, B, u' and the energies at (q, u), internal order.  // q: (nq), u: (nu)
  virtual EngineEquations at(const Eigen::VectorXd& q, const Eigen::VectorXd& u) = 0;
  /// Its forward dynamics at (q, u), from the state set to u' and no more:
  /// the call eigenmass_bench times where EngineCode::forward_call names it.
  virtual void forward(const Eigen::VectorXd& q, const Eigen::VectorXd& u) { at(q, u); }
  /// The masses it compiled where it rounds them (MuJoCo diagonalizes full
  /// inertias), else empty: crosscheck then also compares the in-house
  /// formation given these masses, and does not judge the raw u'.
  virtual std::vector<CompiledMass> compiledMass() { return {}; }
};

/// A URDF robot as an engine with its own reader reads it: the file's text,
/// the URDF joint of each body of the Model in source order, and the import
/// options the Model was loaded with (docs/urdf.md).
struct UrdfSource {
  std::string text;
  std::vector<std::string> joints;  ///< Scene::source_joints
  std::vector<std::string> locked;  ///< joints held fixed (--lock-joint)
  bool balance_inertia = false;
  std::string floating_joint;       ///< the free root's joint name, "" if fixed to the ground
};

/// A method run by the in-house integrators on an engine's own u' (DART's
/// forward dynamics): the engine's formulation apart from its integrator.
struct EngineUdotMethod {
  const char* name = nullptr;     ///< nullptr: the engine offers none
  const char* summary = nullptr;
  const char* colour = nullptr;
  MethodFactory* make = nullptr;
};

/// An engine's own code (solver/registry.hpp's EngineCode): how it runs and
/// what it gives at a state. Its fields are named where it is written.
struct EngineCode {
  /// Integrate from the model's initial state as `spec` says (the engine's
  /// method, one of its schemes), sampled on the output grid; a numerical
  /// failure ends the run with its time and cause; bad settings throw.
  Trajectory (*simulate)(const Model& m, const CheckedRunSpec& spec, const SampleObserver& observe) = nullptr;
  /// Its model of `m` (throws std::runtime_error with the engine's message
  /// when it cannot take the scene), or nullptr: it gives no equations at a state.
  std::unique_ptr<EngineModel> (*model)(const Model& m) = nullptr;
  /// Its own reading of a URDF robot whose Model is `m`, or nullptr: it has
  /// no URDF reader (crosscheck then uses `model`).
  std::unique_ptr<EngineModel> (*urdf)(const Model& m, const UrdfSource& source) = nullptr;
  /// What EngineModel::forward calls ("Simbody realize(Acceleration)"), when
  /// eigenmass_bench times it beside the in-house right-hand sides, or nullptr.
  const char* forward_call = nullptr;
  /// Its library's version, for provenance and --version.
  std::string (*version)() = nullptr;
  /// One line on what crosscheck's "<name>-mass" rows are (engines with compiled masses), else nullptr.
  const char* mass_note = nullptr;
  /// Its u' as a method under the in-house integrators, where it offers one.
  EngineUdotMethod udot_method;
  /// One line on how its A and B are had where it exposes no mass matrix
  /// (Bullet: from its forward dynamics), else nullptr. Such A and B err by
  /// ~eps cond(A), as every u' does.
  const char* equations_note = nullptr;
  /// What of its A, B and u' at a state of `m` is eigenmass's own code
  /// (Bullet's ball, gimbal and free joints' speed maps; its B = A u'), or
  /// nullptr: every entry is the engine's own on every scene.
  EquationsDependence (*dependence)(const Model& m) = nullptr;
  /// One line on what the engine does to this scene that bounds how closely it
  /// can agree with the exact equations (MuJoCo: full inertia tensors rounded),
  /// or "" (also when nullptr): compare reports print and record it.
  std::string (*scene_note)(const Model& m) = nullptr;
  /// Why it cannot take `m` (a joint kind it has no mapping for), or "" (also
  /// when nullptr): such a run is refused in one line before any run starts.
  std::string (*refusal)(const Model& m) = nullptr;
  /// Why it cannot run this mechanism (a closure kind it cannot express,
  /// named with the loop), or "" when it maps every loop, point spring and
  /// drive of `m`; nullptr: it maps no mechanism yet, and every one is refused.
  std::string (*mechanism_refusal)(const Model& m) = nullptr;
  /// Why it would not run `spec` on `m` as asked (MuJoCo: a closure's solref
  /// time below two steps, which it raises to two), or "" (also when nullptr):
  /// refused in one line, naming the option, before any run starts.
  std::string (*settings_refusal)(const Model& m, const RunSpec& spec) = nullptr;
  /// Why it cannot stop `m`'s joints at their limits (docs/theory.md §17; a
  /// joint kind or range its stops cannot take), or "" when it maps them under
  /// its own limit mechanism (its scene_note says how); nullptr: it maps no
  /// joint limits, and every scene with them is refused.
  std::string (*limits_refusal)(const Model& m) = nullptr;
  /// One line on why its equations at a state are the tree's alone on a
  /// mechanism (DART, Bullet: closures, point springs and drives act only
  /// inside its step), or nullptr: crosscheck then judges its A alone, and
  /// prints its B and u' as not exposed.
  const char* mechanism_state = nullptr;
  /// One line on how its closures are soft (MuJoCo's equalities), so that its
  /// u' of a mechanism at a state is not the exact constrained one: crosscheck
  /// prints it and does not judge that u'; nullptr: its closures are exact.
  const char* soft_closures = nullptr;
};

/// One engine: its registry row and its code, written in its own file
/// (reference/<name>.cpp) with named fields.
struct EngineRow {
  EngineInfo info;
  EngineCode code;
};

/// Every engine, in the order every listing uses.
const std::vector<EngineRow>& engineRows();
/// Add every row to the registry (once; later calls do nothing). The
/// engines' dispatch below calls it; programs call it before reading the tables.
void useEngines();
/// The code of engine `e` (not the in-house one), found by its id.
const EngineCode& engineCode(Engine e);
/// The kinds among `kinds` that `m`'s joints have, each with its first body
/// ("gimbal (body 'link1'), free (body 'base')"), or "": for dependence lines.
std::string jointsOfKinds(const Model& m, const std::vector<JointType>& kinds);

/// The first loop of `m` whose kind is not among `mapped`, as one line: "loop
/// 'u' is a universal closure, which <constraints> cannot express (it maps
/// ball, hinge, weld)", or "": an engine's mechanism refusal names the kind.
std::string unmappedLoop(const Model& m, const std::vector<LoopType>& mapped, const std::string& constraints);

}  // namespace em
