#pragma once
/// The `eigenmass-scene/1` format (docs/scene-format.md): the scene as written
/// (parents by name, file order), its validation with one-line errors naming
/// the JSON path, and the model it describes.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solver/mechanism/assembly.hpp"
#include "solver/model.hpp"

namespace em {

/// Bounds of a body's mass (kg) and of its largest principal moment of inertia
/// about the CM (kg m^2), for scenes and URDF imports alike: wide enough for
/// any body a user models (the gallery's smallest: 1e-8 kg, 1.25e-11 kg m^2),
/// narrow enough that products of masses, levers and inertias stay normal
/// doubles (a 5e-324 kg body made Simbody throw; 1e308 kg overflows).
inline constexpr double kMassMin = 1e-12, kMassMax = 1e12;
/// The largest spring stiffness, damping coefficient or drive torque a scene
/// may state (SI: N/m or N m/rad, N s/m or N m s/rad, N or N m), as kMassMax
/// bounds a mass: beyond it a number is no physical one (issue 73, item 11: a k
/// or a torque of 1e300 hung Simbody past 300 s and printed E(0) in 300 digits).
inline constexpr double kMaxForceCoefficient = 1e12;
inline constexpr double kInertiaMin = 1e-24, kInertiaMax = 1e24;
/// Bound of |gravity| (m/s^2): a thousand times Earth's, beyond any vehicle
/// or robot; 1e308 made E(0) a 300-digit number and m g l overflow.
inline constexpr double kGravityMax = 1e4;

/// A body as written in a scene: parent by name ("ground" or a body), file order.
struct BodySpec {
  std::string name, parent;
  double mass = 1.0;
  Mat3 inertia = Mat3::Identity();  ///< about the CM, body frame (matrix entries)
  Joint joint;
  nlohmann::json extra = nlohmann::json::object();  ///< its "x-" keys, kept as written
};

/// A closure as written (`loops`): bodies by name, "ground" for the base.
struct LoopSpec {
  std::string name, body_a, body_b;
  LoopType type = LoopType::Ball;
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();
  Vec3 axis_a = Vec3::UnitZ(), axis_b = Vec3::UnitZ();  ///< unit (hinge)
  nlohmann::json extra = nlohmann::json::object();
};

/// A point spring-damper as written (`forces`, type "spring").
struct ForceSpec {
  std::string name, body_a, body_b;
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();
  double k = 0, c = 0, length = 0;
  nlohmann::json extra = nlohmann::json::object();
};

/// One coordinate of a benchmark's error measure (docs/scene-format.md,
/// "benchmark"): a point fixed in a body, one of its world coordinates.
struct BenchmarkPoint {
  std::string name;          ///< how tables and reports call it ("B0.x")
  std::string body;          ///< a body of the scene (not "ground")
  Vec3 point = Vec3::Zero(); ///< in the body's frame, from its CM (m)
  int axis = 0;              ///< 0, 1, 2: world x, y, z
};

/// The scene as a problem of a benchmark (IFToMM's A01-A05, say): its error
/// measure, the largest |x_run - x_ref| over `measure` at the `outputs` equal
/// output steps up to t_end, and the precision levels a run must stay within.
struct BenchmarkSpec {
  std::string problem;                  ///< "A02": letters, digits, '_' or '-'
  std::vector<BenchmarkPoint> measure;  ///< 1 to kBenchmarkMeasureMax coordinates
  double t_end = 0;                     ///< the problem's horizon (s)
  int outputs = 0;                      ///< output steps over it, t_end / outputs apart
  std::vector<double> levels;           ///< precision levels (m), coarse to fine, strictly decreasing
  /// "solution": the problem's own reference values, where it has one (a closed form, a published
  /// file): the measured coordinates at output steps 1..outputs, row-major (outputs x measure.size());
  /// empty when the problem has none and runs are measured against the reference run.
  std::vector<double> solution;
  nlohmann::json extra = nlohmann::json::object();  ///< its "x-" keys (where each number comes from)
  double outputStep() const { return t_end / outputs; }
  bool hasSolution() const { return !solution.empty(); }
  /// The solution's value of coordinate m at output step k (1..outputs).
  double solutionAt(int k, size_t m) const { return solution[static_cast<size_t>(k - 1) * measure.size() + m]; }
};
inline constexpr int kBenchmarkMeasureMax = 16, kBenchmarkLevelsMax = 4, kBenchmarkOutputsMax = 100000;

/// Largest |g| and |G u| of an initial state that is accepted (m or rad, m/s
/// or rad/s): beyond it the scene is refused naming the loop and the gap.
inline constexpr double kLoopStartTol = 1e-9;
/// Gauss-Newton steps an assembly may take (--assemble, an ensemble member's
/// start): from a start off by ~1e-3 it needs ~4 (quadratic convergence); 50
/// leaves room for starts off by a degree or more.
inline constexpr int kAssembleIterations = 50;
/// m's start assembled onto its loops at the scene's tolerance (kLoopStartTol
/// / 1000, kAssembleIterations): what --assemble and an ensemble's members
/// use. Throws std::runtime_error ("... from the <what> (gap g) in 50 steps")
/// where Gauss-Newton does not close them.
Assembly assembledStart(const Model& m, const std::string& what);

/// A scene as written: bodies in file order and the run defaults.
struct SceneSpec {
  std::string name;
  Vec3 gravity{0, 0, -9.81};
  std::vector<BodySpec> bodies;
  std::vector<LoopSpec> loops;    ///< closures (docs/scene-format.md, "Mechanisms")
  std::vector<ForceSpec> forces;  ///< point spring-dampers
  double t_end = 10.0, output_dt = 0.01;  ///< simulate.t_end, simulate.output_dt
  bool assemble = false;  ///< simulate.assemble: project q0, then u0, onto the loops instead of refusing an open start
  nlohmann::json extra = nlohmann::json::object();  ///< top-level "x-" keys, kept as written
  std::optional<BenchmarkSpec> benchmark;  ///< "benchmark": the scene as a benchmark problem
};

/// Parse and validate scene text. Throws InputError (JSON path: what) on any defect.
SceneSpec parseSceneSpec(const std::string& text);

/// A joint's "control" object at `path` (docs/scene-format.md): a PD loop or a
/// torque table for joint j. `urdf_effort` is a URDF joint's <limit effort>,
/// which a PD loop's "effort": "urdf" takes (refused without one).
JointControl parseJointControl(const nlohmann::json& v, const std::string& path, const Joint& j,
                               std::optional<double> urdf_effort = std::nullopt);

/// The scene as `eigenmass-scene/1` text that parseSceneSpec reads back to
/// the same spec: one body per line, numbers to 17 significant digits.
std::string sceneJson(const SceneSpec& spec);

/// Letters, digits, '_' and '-', 1 to 64 of them: what names in a scene may be.
bool isSceneName(const std::string& name);

/// The model of a scene as written: parents resolved by name, then the
/// solver's buildModel. Throws InputError naming `bodies[i].name` or
/// `bodies[i].parent` (file indices).
/// With spec.assemble, the start is assembled onto the loops first
/// (assembleStart) and `assembled` (when given) says by how much.
Model buildModel(const SceneSpec& spec, Assembly* assembled = nullptr);

}  // namespace em
