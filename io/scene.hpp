#pragma once
/// A scene ready to run, from whatever file describes it (`eigenmass-scene/1`
/// JSON or URDF, told by the extension): the model, the run defaults the file
/// states and where it came from. Every error is one line naming the file and
/// the key, link or joint (docs/scene-format.md, docs/urdf.md).
#include <optional>
#include <string>
#include <vector>

#include "io/scene_json.hpp"
#include "io/urdf.hpp"
#include "solver/mechanism/assembly.hpp"
#include "solver/model.hpp"

namespace em {

/// Where a scene came from, as every report records it.
struct SceneSource {
  std::string file;                          ///< where it was read from
  std::string format = "eigenmass-scene/1";  ///< or "urdf"
  std::string sha256;                        ///< of the file's bytes (empty for text given in memory)
  std::vector<std::string> notes;            ///< what an import changed (URDF: repairs, locked joints)
  std::optional<Assembly> assembly;          ///< simulate.assemble / --assemble: how far the start was moved onto the loops
};

struct Scene {
  Model model;
  double t_end = 10.0, output_dt = 0.01;  ///< the file's run defaults (simulate.t_end, .output_dt)
  SceneSource source;
  std::vector<std::string> source_joints; ///< URDF: the joint of each body, file order, as written
  std::optional<BenchmarkSpec> benchmark; ///< the file's "benchmark" (JSON scenes only)
};

/// Read, validate and build a scene file. Throws std::runtime_error("file: path: what").
/// `urdf` applies to URDF files; asking it of a JSON scene is an error.
/// `assemble` (--assemble) asks what the scene's simulate.assemble does.
Scene loadScene(const std::string& path, const UrdfOptions& urdf = {}, bool assemble = false);
/// The same from `eigenmass-scene/1` text in memory; `source` names it in errors.
Scene loadSceneText(const std::string& text, const std::string& source, bool assemble = false);
/// The same from URDF text in memory.
Scene loadUrdfText(const std::string& text, const std::string& source, const UrdfOptions& options = {});
/// A URDF file as a scene spec (io/urdf.hpp's importUrdf), errors naming the file.
UrdfScene importUrdfFile(const std::string& path, const UrdfOptions& options);

}  // namespace em
