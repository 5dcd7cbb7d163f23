#include "io/scene.hpp"

#include "io/digest.hpp"
#include "io/json_input.hpp"
#include "io/scene_json.hpp"
#include "io/urdf.hpp"

namespace em {

Scene loadSceneText(const std::string& text, const std::string& source) {
  try {
    const SceneSpec spec = parseSceneSpec(text);
    Scene s;
    s.model = buildModel(spec);
    s.t_end = spec.t_end;
    s.output_dt = spec.output_dt;
    s.file = source;
    return s;
  } catch (const InputError& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
}

Scene loadUrdfText(const std::string& text, const std::string& source, const UrdfOptions& options) {
  try {
    const UrdfScene u = importUrdf(text, source, options);
    Scene s;
    s.model = buildModel(u.spec);
    s.t_end = u.spec.t_end;
    s.output_dt = u.spec.output_dt;
    s.file = source;
    s.format = "urdf";
    s.notes = u.notes;
    s.source_joints = u.joint_names;
    return s;
  } catch (const InputError& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
}

Scene loadScene(const std::string& path, const UrdfOptions& urdf) {
  const bool is_urdf = isUrdfPath(path);
  if (!is_urdf && urdf.any())
    throw std::runtime_error(std::string(urdf.balance_inertia ? "--balance-inertia" : "--lock-joint") +
                             ": applies to URDF files only, not to " + path);
  const std::string text = readFile(path, is_urdf ? "URDF file" : "scene file");
  Scene s = is_urdf ? loadUrdfText(text, path, urdf) : loadSceneText(text, path);
  s.sha256 = sha256Hex(text);
  return s;
}

}  // namespace em
