#include "io/scene.hpp"

#include "io/digest.hpp"
#include "io/json_input.hpp"
#include "io/scene_json.hpp"
#include "io/urdf.hpp"

namespace em {

namespace {

// A defect found at a JSON path, a link or a joint becomes one line naming the file.
template <class Read>
auto inFile(const std::string& source, Read&& read) -> decltype(read()) {
  try {
    return read();
  } catch (const InputError& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
}

Scene fromSpec(SceneSpec spec, const std::string& source, bool assemble = false) {
  Scene s;
  spec.assemble = spec.assemble || assemble;
  Assembly a;
  s.model = buildModel(spec, &a);
  if (spec.assemble) s.source.assembly = a;
  s.t_end = spec.t_end;
  s.output_dt = spec.output_dt;
  s.benchmark = spec.benchmark;
  s.source.file = source;
  return s;
}

}  // namespace

Scene loadSceneText(const std::string& text, const std::string& source, bool assemble) {
  return inFile(source, [&] { return fromSpec(parseSceneSpec(text), source, assemble); });
}

Scene loadUrdfText(const std::string& text, const std::string& source, const UrdfOptions& options) {
  return inFile(source, [&] {
    const UrdfScene u = importUrdf(text, source, options);
    Scene s = fromSpec(u.spec, source);
    s.source.format = "urdf";
    s.source.notes = u.notes;
    s.source_joints = u.joint_names;
    return s;
  });
}

UrdfScene importUrdfFile(const std::string& path, const UrdfOptions& options) {
  const std::string text = readFile(path, "URDF file");
  return inFile(path, [&] { return importUrdf(text, path, options); });
}

Scene loadScene(const std::string& path, const UrdfOptions& urdf, bool assemble) {
  const bool is_urdf = isUrdfPath(path);
  if (!is_urdf && urdf.any())
    throw std::runtime_error(urdf.firstOption() + ": applies to URDF files only, not to " + path);
  const std::string text = readFile(path, is_urdf ? "URDF file" : "scene file");
  if (is_urdf && assemble) throw std::runtime_error("--assemble: a URDF robot has no loops to assemble onto (" + path + ")");
  Scene s = is_urdf ? loadUrdfText(text, path, urdf) : loadSceneText(text, path, assemble);
  s.source.sha256 = sha256Hex(text);
  return s;
}

}  // namespace em
