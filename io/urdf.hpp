#pragma once
/// URDF robots as scenes (docs/urdf.md). liburdfdom parses the file; this
/// maps it: the root link held by the ground (or freed by a free joint,
/// --floating-base), revolute and continuous joints to revolute joints,
/// prismatic to prismatic, floating to free, fixed (and --lock-joint) joints merged into their
/// parent with the parallel-axis theorem, every frame turned world-aligned at
/// the zero configuration. Errors are one line naming the link or joint.
#include <optional>
#include <string>
#include <vector>

#include "io/scene_json.hpp"

namespace em {

/// What a user may ask of an import beyond the file (command-line options).
struct UrdfOptions {
  bool balance_inertia = false;          ///< --balance-inertia: MuJoCo's balanceinertia repair
  std::vector<std::string> lock_joints;  ///< --lock-joint: held at zero and merged like a fixed joint
  bool floating_base = false;            ///< --floating-base: the root link moves on a free joint (kFloatingBaseJoint)
  bool damping = false;                  ///< --urdf-damping: <dynamics damping> as joint dampers
  bool ignore_friction = false;          ///< --urdf-ignore-friction: run without a <dynamics friction> (noted), refused otherwise under --urdf-damping
  std::optional<double> limits_restitution;  ///< --urdf-limits E: <limit lower upper> as stops of restitution E
  std::string control_file;              ///< --control FILE: joint controllers by URDF joint name (eigenmass-control/1)
  bool any() const {
    return balance_inertia || !lock_joints.empty() || floating_base || damping || ignore_friction || limits_restitution || !control_file.empty();
  }
  /// The first option set, as the command line spells it (for "applies to URDF files only").
  std::string firstOption() const {
    return balance_inertia ? "--balance-inertia" : floating_base ? "--floating-base" : !lock_joints.empty() ? "--lock-joint"
         : damping ? "--urdf-damping" : ignore_friction ? "--urdf-ignore-friction" : limits_restitution ? "--urdf-limits" : "--control";
  }
};

/// The name of the free joint --floating-base gives the root link.
inline constexpr const char* kFloatingBaseJoint = "floating_base";

/// A URDF as a scene: the spec (bodies in the file order of their joints,
/// provenance in `x-` keys) and what the import did beyond a plain mapping.
struct UrdfScene {
  SceneSpec spec;
  std::vector<std::string> joint_names;  ///< the URDF joint of spec.bodies[i], as written
  std::vector<std::string> notes;        ///< repairs and locked joints, one line each
};

/// Import URDF `text` (`source` names it in provenance). Throws InputError
/// ("link 'x'" or "joint 'y'": what is wrong) before any computation.
UrdfScene importUrdf(const std::string& text, const std::string& source, const UrdfOptions& options);

/// True when `path` names a URDF file (by its extension, ".urdf", any case).
bool isUrdfPath(const std::string& path);

}  // namespace em
