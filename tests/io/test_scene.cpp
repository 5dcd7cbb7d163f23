// Scene loading: every malformed scene names its file and JSON path in one line;
// valid scenes get their defaults, normalizations and conventions.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "support.hpp"

using namespace em;

namespace {

std::string errorOf(const std::string& path) {
  try {
    loadScene(path);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

const char* kMinimal = R"({"format": "eigenmass-scene/1", "name": "one", "x-note": {"free": true},
  "bodies": [{"name": "rod", "parent": "ground", "mass": 2, "inertia": [1, 2, 2.5, 0.1, -0.2, 0.3],
              "joint": {"type": "ball", "in_parent": [0, 0, 0], "in_body": [0, 0, 1], "q0": [2, 0, 0, 0]}}]})";

}  // namespace

TEST_CASE("every malformed scene fails with one line naming the file and the JSON path", "[scene]") {
  const std::string dir = test::sourcePath("tests/scenes/malformed/");
  std::ifstream in(dir + "expected.json");
  const nlohmann::json expected = nlohmann::json::parse(in);
  REQUIRE(expected.size() >= 20);
  // The manifest covers every scene in the folder, and no scene is missing.
  size_t files = 0;
  for (auto& f : std::filesystem::directory_iterator(dir)) files += f.path().filename() != "expected.json";
  CHECK(files == expected.size());
  for (auto it = expected.begin(); it != expected.end(); ++it) {
    const std::string file = dir + it.key();
    const std::string msg = errorOf(file);
    INFO(it.key() << " -> " << msg);
    CHECK(msg.rfind(file + ": " + it.value()["path"].get<std::string>() + ": ", 0) == 0);
    CHECK(msg.find(it.value()["phrase"].get<std::string>()) != std::string::npos);
    CHECK(msg.find('\n') == std::string::npos);
    CHECK(msg.find('\x1b') == std::string::npos);  // no escape code reaches the terminal
    CHECK(msg.size() < 400);                        // a quoted value is bounded (a 20000-number mass)
  }
}

TEST_CASE("tiny axes normalize stably - only an exactly zero axis is refused", "[scene]") {
  auto withAxis = [](const std::string& axis) {
    std::string s = kMinimal;
    s.replace(s.find(R"("type": "ball")"), 14, R"("type": "revolute", "axis": )" + axis);
    s.replace(s.find(R"("q0": [2, 0, 0, 0])"), 18, R"("q0": [0.3])");
    return s;
  };
  CHECK(loadSceneText(withAxis("[1e-160, 0, 0]"), "tiny").model.bodies[0].joint.axis[0] == Vec3::UnitX());
  CHECK(loadSceneText(withAxis("[0, 0, 1e-300]"), "tinier").model.bodies[0].joint.axis[0] == Vec3::UnitZ());
  CHECK(loadSceneText(withAxis("[1e300, 1e300, 0]"), "huge").model.bodies[0].joint.axis[0].norm() == Approx(1.0).epsilon(1e-15));
  CHECK_THROWS_WITH(loadSceneText(withAxis("[0, 0, 0]"), "zero"), Catch::Contains("zero axis"));
}

TEST_CASE("a missing file is one line naming it", "[scene]") {
  CHECK_THROWS_WITH(loadScene("/nonexistent/x.json"), "/nonexistent/x.json: cannot open the scene file");
}

TEST_CASE("defaults - normalization and x- keys of a valid scene", "[scene]") {
  const Scene scene = loadSceneText(kMinimal, "mem");
  const Model& m = scene.model;
  CHECK(m.gravity == Vec3(0, 0, -9.81));
  CHECK(scene.t_end == 10.0);
  const Body& b = m.bodies[0];
  CHECK(b.joint.q0 == Eigen::Vector4d(1, 0, 0, 0));  // [2,0,0,0] normalized on read
  CHECK(b.joint.u0 == Eigen::Vector3d::Zero());
  // Six-number inertia: the matrix entries themselves, Ixy = J[0][1].
  CHECK(b.J(0, 1) == 0.1);
  CHECK(b.J(1, 0) == 0.1);
  CHECK(b.J(0, 2) == -0.2);
  CHECK(b.J(1, 2) == 0.3);
  CHECK_FALSE(m.has_springs);
}

TEST_CASE("a thin plate (triangle equality) is valid - a slightly thinner one is not", "[scene]") {
  auto with = [](const std::string& inertia) {
    std::string s = kMinimal;
    return s.replace(s.find("[1, 2, 2.5, 0.1, -0.2, 0.3]"), 27, inertia);
  };
  CHECK_NOTHROW(loadSceneText(with("[0.1, 0.2, 0.3]"), "plate"));
  CHECK_THROWS_WITH(loadSceneText(with("[0.1, 0.2, 0.30001]"), "plate"), Catch::Contains("triangle"));
}

TEST_CASE("axes are normalized and universal axes are checked after normalization", "[scene]") {
  const Model m = test::loadData("tree_mixed.json");
  for (const Body& b : m.bodies) {
    if (b.joint.type == JointType::Revolute || b.joint.type == JointType::Universal)
      CHECK(std::abs(b.joint.axis[0].norm() - 1) < 1e-15);
    if (b.name == "forearm") CHECK((b.joint.axis[0] - Vec3(1, 1, 0) / std::sqrt(2.0)).norm() < 1e-15);
  }
}

TEST_CASE("every data scene loads and the list of data scenes is complete", "[scene]") {
  size_t files = 0;
  for (auto& f : std::filesystem::directory_iterator(test::sourcePath("data/scenes")))
    files += f.path().extension() == ".json";
  CHECK(files == test::dataScenes().size());
  for (const auto& s : test::dataScenes()) CHECK_NOTHROW(test::loadData(s));
}
