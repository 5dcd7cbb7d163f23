// `eigenmass import`: a URDF robot as the equivalent eigenmass-scene/1 file,
// with its provenance in x- keys, for a user to inspect and edit.
#include <cstdio>
#include <map>
#include <iostream>
#include <memory>

#include "app/cli.hpp"
#include "io/atomic_file.hpp"
#include "io/urdf.hpp"

namespace em::cli {

namespace {

struct ImportArgs {
  SceneArg robot;
  std::string out;
};

int runImport(const ImportArgs& a) {
  if (!isUrdfPath(a.robot.path)) throw std::runtime_error(a.robot.path + ": not a URDF file (expected the extension .urdf)");
  if (!a.out.empty()) prepareOutput("--out", a.out, {a.robot.path});
  const UrdfScene u = importUrdfFile(a.robot.path, a.robot.urdf);
  const std::string text = sceneJson(u.spec);
  loadSceneText(text, "(the scene written)");  // what is written must load as written
  if (a.out.empty()) std::cout << text;
  else writeAtomic(a.out, "scene", [&](std::ostream& o) { o << text; });
  std::map<std::string, int> kinds;  // the joints as imported, by kind
  for (const BodySpec& b : u.spec.bodies) ++kinds[jointTypeName(b.joint.type)];
  std::string joints;
  for (const auto& [kind, count] : kinds) joints += (joints.empty() ? "" : ", ") + std::to_string(count) + " " + kind;
  std::fprintf(stderr, "%s: %zu moving bodies (joints: %s), %zu links held by the ground%s%s\n", u.spec.name.c_str(),
               u.spec.bodies.size(), joints.c_str(), u.spec.extra["x-urdf-ground-links"].size(),
               a.out.empty() ? "" : " -> ", a.out.c_str());
  for (const std::string& n : u.notes) std::fprintf(stderr, "  note: %s\n", n.c_str());
  return 0;
}

}  // namespace

void addImport(CLI::App& app) {
  auto* cmd = app.add_subcommand("import", "Write a URDF robot as the equivalent eigenmass-scene/1 file (docs/urdf.md)");
  auto a = std::make_shared<ImportArgs>();
  addSceneArg(cmd, a->robot);
  cmd->get_option("scene")->description("URDF robot (.urdf; docs/urdf.md): a JSON scene is refused, it is one already");
  cmd->add_option("--out", a->out, "Scene file to write (never the input); default: standard output");
  cmd->callback([a] { guarded([&] { return runImport(*a); }); });
}

}  // namespace em::cli
