// URDF import: the mapping against hand-computed closed forms (rotated joint
// frames, offset and rotated inertials, fixed-joint merging), equivalences
// (a fixed child = the same mass written into its parent; import -> JSON ->
// load), names, options, and the malformed corpus with its messages.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "io/urdf.hpp"
#include "solver/formation.hpp"
#include "support.hpp"

using namespace em;

namespace {

// Written decimals (0.1, 0.5) and one rotation by pi/2 from rpy: a few ulps.
constexpr double kExact = 1e-14;

std::string robot(const std::string& body) { return "<?xml version=\"1.0\"?><robot name=\"r\"><link name=\"base\"/>" + body + "</robot>"; }

std::string link(const std::string& name, const std::string& inertial) { return "<link name=\"" + name + "\">" + inertial + "</link>"; }

std::string inertial(const std::string& xyz, const std::string& rpy, double m, const std::string& inertia) {
  return "<inertial><origin xyz=\"" + xyz + "\" rpy=\"" + rpy + "\"/><mass value=\"" + std::to_string(m) + "\"/><inertia " +
         inertia + "/></inertial>";
}

std::string joint(const std::string& name, const std::string& type, const std::string& parent, const std::string& child,
                  const std::string& xyz, const std::string& rpy, const std::string& axis = "1 0 0") {
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/><origin xyz=\"" + xyz + "\" rpy=\"" + rpy + "\"/><axis xyz=\"" + axis + "\"/></joint>";
}

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

const char* kDiag123 = "ixx=\"1\" iyy=\"2\" izz=\"3\" ixy=\"0\" ixz=\"0\" iyz=\"0\"";

// Largest difference of A and B between two models at random states.
double maxDiffAB(const Model& a, const Model& b, int states = 10) {
  std::mt19937 rng(7);
  Eigen::VectorXd q, u;
  Workspace wa(a), wb(b);
  double worst = 0;
  for (int k = 0; k < states; ++k) {
    randomState(a, rng, q, u);
    formEquations(a, q.data(), u.data(), wa);
    formEquations(b, q.data(), u.data(), wb);
    worst = std::max({worst, (wa.A - wb.A).cwiseAbs().maxCoeff(), (wa.B - wb.B).cwiseAbs().maxCoeff()});
  }
  return worst;
}

std::string errorOf(const std::string& path, const UrdfOptions& opt = {}) {
  try {
    loadScene(path, opt);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a rotated joint frame and an offset, rotated inertial map to the closed form", "[urdf]") {
  // Joint frame turned by +90 deg about z at (0, 0, 1): its x axis is the world's y.
  // The inertial sits 0.5 along the link's x (world y) and is itself turned by
  // 90 deg about its x (so its y and z swap): diag(1, 2, 3) -> diag(1, 3, 2) in
  // the link frame -> diag(3, 1, 2) in the world.
  const std::string text = robot(link("arm", inertial("0.5 0 0", "1.5707963267948966 0 0", 2, kDiag123)) +
                                 joint("hinge", "continuous", "base", "arm", "0 0 1", "0 0 1.5707963267948966"));
  const Scene s = loadUrdfText(text, "mem");
  REQUIRE(s.model.n() == 1);
  const Body& b = s.model.bodies[0];
  CHECK((b.joint.axis[0] - Vec3(0, 1, 0)).norm() < kExact);
  CHECK((b.joint.in_parent - Vec3(0, 0, 1)).norm() < kExact);  // from the world origin (ground)
  CHECK((b.joint.in_body - Vec3(0, -0.5, 0)).norm() < kExact);  // joint point from the CM at (0, 0.5, 1)
  CHECK(b.mass == 2);
  CHECK((b.J - Vec3(3, 1, 2).asDiagonal().toDenseMatrix()).norm() < kExact);
  CHECK(s.model.qNames() == std::vector<std::string>{"hinge.q0"});
  CHECK(s.source.format == "urdf");
  CHECK(s.source_joints == std::vector<std::string>{"hinge"});
}

TEST_CASE("a fixed child is merged by the parallel-axis theorem", "[urdf]") {
  // Two unit point-like masses (inertia 0.1 E each) 1 m apart along z, the
  // second fixed to the first: mass 2, CM halfway, inertia 0.2 E + 2 (0.5^2) (E - e_z e_z^T).
  const std::string small = "ixx=\"0.1\" iyy=\"0.1\" izz=\"0.1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"";
  const std::string text = robot(link("a", inertial("0 0 0", "0 0 0", 1, small)) + link("tip", inertial("0 0 0", "0 0 0", 1, small)) +
                                 joint("j", "continuous", "base", "a", "0 0 0", "0 0 0") +
                                 joint("weld", "fixed", "a", "tip", "0 0 -1", "0 0 0"));
  const Scene s = loadUrdfText(text, "mem");
  REQUIRE(s.model.n() == 1);
  const Body& b = s.model.bodies[0];
  CHECK(b.mass == 2);
  CHECK((b.joint.in_body - Vec3(0, 0, 0.5)).norm() < kExact);
  CHECK((b.J - Vec3(0.7, 0.7, 0.2).asDiagonal().toDenseMatrix()).norm() < kExact);
}

TEST_CASE("a fixed child equals the same mass written into its parent", "[urdf]") {
  // Two-link arm whose forearm carries a fixed, offset and turned tool; the
  // same arm with the tool's mass folded by hand into the forearm's inertial
  // is the reference (both go through the importer's frame arithmetic, only one through the merge).
  const std::string upper = link("upper", inertial("0 0 -0.3", "0 0 0", 1.5, "ixx=\"0.05\" iyy=\"0.04\" izz=\"0.02\" ixy=\"0.001\" ixz=\"0\" iyz=\"0\""));
  const std::string joints = joint("shoulder", "continuous", "base", "upper", "0 0 0", "0.3 0 0", "0 1 0") +
                             joint("elbow", "continuous", "upper", "fore", "0 0 -0.6", "0 0.2 0", "1 0 0");
  const std::string fore = link("fore", inertial("0 0 -0.25", "0 0 0", 1, "ixx=\"0.03\" iyy=\"0.03\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\""));
  const std::string tool = link("tool", inertial("0 0 0", "0 0 0", 0.5, "ixx=\"0.002\" iyy=\"0.002\" izz=\"0.002\" ixy=\"0\" ixz=\"0\" iyz=\"0\""));
  const Scene merged = loadUrdfText(robot(upper + fore + tool + joints + joint("weld", "fixed", "fore", "tool", "0 0 -0.5", "0.4 0.1 0")), "mem");
  // By hand: masses 1 at z = -0.25 and 0.5 at z = -0.5 (the tool's frame turn
  // does not matter: its inertia is isotropic). CM z = -1/3; inertia about it:
  // xx = yy = 0.03 + 0.002 + 1 (1/12)^2 + 0.5 (1/6)^2, zz = 0.01 + 0.002.
  const double xx = 0.032 + 1.0 / 144 + 0.5 / 36;
  const std::string folded = link("fore", inertial("0 0 " + num(-1.0 / 3), "0 0 0", 1.5,
                                                   "ixx=\"" + num(xx) + "\" iyy=\"" + num(xx) +
                                                       "\" izz=\"0.012\" ixy=\"0\" ixz=\"0\" iyz=\"0\""));
  const Scene by_hand = loadUrdfText(robot(upper + folded + joints), "mem");
  // Written to 17 digits: the two agree to round-off of O(1) entries.
  CHECK(maxDiffAB(merged.model, by_hand.model) < kExact);
  CHECK(merged.model.bodies[1].mass == 1.5);
}

TEST_CASE("an imported robot written as JSON loads back to the same equations", "[urdf]") {
  for (const char* name : {"ur5", "z1", "solo12"}) {
    INFO(name);
    const std::string path = test::sourcePath(std::string("data/robots/") + name + ".urdf");
    const UrdfScene u = importUrdf(readFile(path, "URDF"), path, {});
    const Scene direct = loadScene(path);
    const Scene back = loadSceneText(sceneJson(u.spec), "written");
    // 17 significant digits round-trip every double; the axis is normalized again on read.
    CHECK(maxDiffAB(direct.model, back.model) < 1e-15);
    CHECK(back.model.qNames() == direct.model.qNames());
  }
}

TEST_CASE("bodies follow the file's joint order and coordinates are named after the URDF joints", "[urdf]") {
  const Scene ur5 = loadScene(test::sourcePath("data/robots/ur5.urdf"));
  CHECK(ur5.model.qNames() == std::vector<std::string>{"shoulder_pan_joint.q0", "shoulder_lift_joint.q0", "elbow_joint.q0",
                                                        "wrist_1_joint.q0", "wrist_2_joint.q0", "wrist_3_joint.q0"});
  // Names outside the scene's letters are mapped ('.' -> '_'); the URDF's own names stay in source_joints.
  const Scene hand = loadScene(test::sourcePath("data/robots/allegro_right_hand.urdf"), {true, {}});
  CHECK(hand.model.qNames()[0] == "joint_0_0.q0");
  CHECK(hand.source_joints[0] == "joint_0.0");
  CHECK(hand.model.n() == 16);
}

TEST_CASE("published inertias that violate the triangle inequality are refused, or repaired on request", "[urdf]") {
  const std::string path = test::sourcePath("data/robots/allegro_right_hand.urdf");
  CHECK_THAT(errorOf(path), Catch::StartsWith(path + ": link 'link_3.0': inertia violates the triangle inequality"));
  const Scene s = loadScene(path, {true, {}});
  REQUIRE(s.source.notes.size() == 4);  // link_3.0, 7.0, 11.0 (one finger design) and the thumb's link_15.0
  CHECK_THAT(s.source.notes[0], Catch::Contains("set to their mean") && Catch::Contains("--balance-inertia"));
}

TEST_CASE("a locked joint is merged like a fixed one and noted", "[urdf]") {
  const std::string path = test::sourcePath("data/robots/ur5.urdf");
  const Scene s = loadScene(path, {false, {"wrist_3_joint"}});
  CHECK(s.model.n() == 5);
  REQUIRE(s.source.notes.size() == 1);
  CHECK_THAT(s.source.notes[0], Catch::Contains("wrist_3_joint") && Catch::Contains("--lock-joint"));
  CHECK_THAT(errorOf(path, {false, {"nope"}}), Catch::Contains("--lock-joint: no joint named 'nope'"));
  CHECK_THAT(errorOf(path, {false, {"ee_fixed_joint"}}), Catch::Contains("--lock-joint: joint 'ee_fixed_joint' is fixed already"));
  // Options of the URDF importer are refused for a JSON scene rather than ignored.
  CHECK_THAT(errorOf(test::sourcePath("data/scenes/pendulum5.json"), {true, {}}),
             Catch::StartsWith("--balance-inertia: applies to URDF files only"));
}

TEST_CASE("every malformed URDF fails with one line naming the file and the link or joint", "[urdf]") {
  const std::string dir = test::sourcePath("tests/robots/malformed/");
  std::ifstream in(dir + "expected.json");
  const nlohmann::json expected = nlohmann::json::parse(in);
  size_t files = 0;
  for (auto& f : std::filesystem::directory_iterator(dir)) files += f.path().extension() == ".urdf";
  CHECK(files == expected.size());
  for (auto it = expected.begin(); it != expected.end(); ++it) {
    const std::string path = dir + it.key(), message = errorOf(path);
    INFO(message);
    CHECK_THAT(message, Catch::StartsWith(path + ": ") && Catch::Contains(it.value().get<std::string>()));
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("xacro text inside XML comments does not make an expanded URDF a xacro file", "[urdf]") {
  // PAL's published TALOS files keep <xacro:...> lines in comments (issue 42, bug 1).
  const std::string commented = robot("<!-- <xacro:include filename=\"arm.xacro\"/> -->" +
                                      link("arm", inertial("0 0 0", "0 0 0", 1, kDiag123)) +
                                      joint("j1", "continuous", "base", "arm", "0 0 1", "0 0 0"));
  const UrdfScene s = importUrdf(commented, "commented.urdf", {});
  CHECK(s.spec.bodies.size() == 1);
  CHECK_THROWS_WITH(importUrdf(robot("<xacro:arm parent=\"base\"/>"), "x.urdf", {}), Catch::Contains("a xacro file"));
}

TEST_CASE("a URDF's joint dynamics and a control file are imported only as asked", "[urdf][control]") {
  // One revolute joint with damping 0.7, friction 0.2, limits [-1, 2] and effort 5.
  const std::string text = robot(link("arm", inertial("0 0 0", "0 0 0", 1.0, kDiag123)) +
                                 "<joint name=\"j\" type=\"revolute\"><parent link=\"base\"/><child link=\"arm\"/><origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>"
                                 "<axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"2\" effort=\"5\" velocity=\"3\"/>"
                                 "<dynamics damping=\"0.7\" friction=\"0.2\"/></joint>");
  SECTION("without options: neither damper nor stops (the engine study's robots stay as they were)") {
    const UrdfScene s = importUrdf(text, "r.urdf", {});
    const BodySpec& b = s.spec.bodies[0];
    CHECK_FALSE(b.joint.has_spring);
    CHECK_FALSE(b.joint.limits);
    CHECK_FALSE(b.joint.control);
  }
  SECTION("--urdf-damping refuses the friction it cannot model, unless told to run without it") {
    UrdfOptions o;
    o.damping = true;
    CHECK_THROWS_WITH(importUrdf(text, "r.urdf", o), Catch::Contains("joint 'j'") && Catch::Contains("friction") && Catch::Contains("--urdf-ignore-friction"));
    o.ignore_friction = true;
    const UrdfScene s = importUrdf(text, "r.urdf", o);
    REQUIRE(s.spec.bodies[0].joint.has_spring);
    CHECK(s.spec.bodies[0].joint.spring.c[0] == 0.7);
    CHECK(s.spec.bodies[0].joint.spring.k[0] == 0);
    CHECK(std::any_of(s.notes.begin(), s.notes.end(), [](const std::string& n) { return n.find("not modelled") != std::string::npos; }));
  }
  SECTION("--urdf-limits E: the stops, with the restitution asked for") {
    UrdfOptions o;
    o.limits_restitution = 0.3;
    const UrdfScene s = importUrdf(text, "r.urdf", o);
    const BodySpec& b = s.spec.bodies[0];
    REQUIRE(b.joint.limits);
    CHECK(b.joint.limits->lower[0] == -1);
    CHECK(b.joint.limits->upper[0] == 2);
    CHECK(b.joint.limits->restitution == 0.3);
  }
  SECTION("--control: controllers by URDF joint name, \"effort\": \"urdf\" at <limit effort>") {
    const std::string dir = std::filesystem::temp_directory_path() / ("em_control_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto write = [&](const std::string& name, const std::string& body) {
      std::ofstream(dir + "/" + name) << body;
      return dir + "/" + name;
    };
    UrdfOptions o;
    o.control_file = write("ok.json", R"({"format": "eigenmass-control/1", "joints": {"j": {"type": "pd", "kp": 10, "kd": 1, "effort": "urdf",
                                         "target": {"type": "sine", "offset": 0, "amplitude": 0.2, "frequency_hz": 1}}}})");
    const UrdfScene s = importUrdf(text, "r.urdf", o);
    const BodySpec& b = s.spec.bodies[0];
    REQUIRE(b.joint.control);
    CHECK(b.joint.control->effort[0] == 5);
    o.control_file = write("bad.json", R"({"format": "eigenmass-control/1", "joints": {"elbow": {"type": "table", "t": [0], "tau": [1]}}})");
    CHECK_THROWS_WITH(importUrdf(text, "r.urdf", o), Catch::Contains("joints.elbow") && Catch::Contains("no moving joint of that name"));
    o.control_file = write("order.json", R"({"format": "eigenmass-control/1", "joints": {"j": {"type": "table", "t": [0, 1, 0.5], "tau": [1, 2, 3]}}})");
    CHECK_THROWS_WITH(importUrdf(text, "r.urdf", o), Catch::Contains("t[2]") && Catch::Contains("not after"));
    // Two joints sampled at two periods: named in the control file, not in the robot (a helper's hostile pass).
    const std::string two = robot(link("a", inertial("0 0 0", "0 0 0", 1.0, kDiag123)) + link("b", inertial("0 0 0", "0 0 0", 1.0, kDiag123)) +
                                  joint("j1", "continuous", "base", "a", "0 0 0", "0 0 0") + joint("j2", "continuous", "a", "b", "1 0 0", "0 0 0"));
    o.control_file = write("two.json", R"({"format": "eigenmass-control/1", "joints": {
        "j1": {"type": "table", "t": [0], "tau": [1], "period": 0.01}, "j2": {"type": "table", "t": [0], "tau": [1], "period": 0.02}}})");
    CHECK_THROWS_WITH(importUrdf(two, "r.urdf", o), Catch::Contains("two.json") && Catch::Contains("joints.j2.period") && Catch::Contains("shares one period"));
    std::filesystem::remove_all(dir);
  }
}
