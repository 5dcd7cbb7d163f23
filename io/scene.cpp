#include "io/scene.hpp"

#include "io/json_input.hpp"
#include "io/scene_json.hpp"

namespace em {

Scene loadSceneText(const std::string& text, const std::string& source) {
  try {
    const SceneSpec spec = parseSceneSpec(text);
    Scene s{buildModel(spec), spec.t_end, spec.output_dt, source};
    return s;
  } catch (const InputError& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
}

Scene loadScene(const std::string& path) { return loadSceneText(readFile(path, "scene file"), path); }

}  // namespace em
