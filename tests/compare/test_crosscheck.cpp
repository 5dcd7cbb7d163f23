// Published robots against an independent URDF reader: MuJoCo compiles each
// file itself; A, B and u' agree with the in-house import at random states.
#include <catch2/catch.hpp>

#include "compare/crosscheck.hpp"
#include "reference/engine.hpp"
#include "support.hpp"

using namespace em;

namespace {

// The bound for MuJoCo's own reading of a URDF: its compiler rounds a
// full inertia tensor when diagonalizing it (1e-12 absolute on the
// off-diagonals), 3e-8 relative in A on the Z1 arm's small links (measured).
constexpr double kMujocoRaw = 1e-7;
// MuJoCo against the in-house formation given MuJoCo's compiled masses, CMs and
// inertias, and Simbody against the same Model: round-off only (measured at
// most 1.7e-14, on Z1's u', whose cond(A) amplifies eps).
constexpr double kRoundOff = 1e-12;

struct Robot {
  const char* file;
  UrdfOptions options;
};

}  // namespace

namespace {

// u' of a backward-stable solve errs by ~eps cond(A) (support.hpp's
// udotTolerance, 4 eps cond(A)): cond(A) reaches 2e6 on chain50, 1.8e-9.
constexpr double kUdotCond = 2e-9;

// Every row of a cross-check within its bound: MuJoCo's own reading within
// kMujocoRaw (u' within 1e-6: A's rounding times cond(A), Z1 reaches 2.3e-7,
// docs/urdf.md), every other row's A and B round-off, u' within `udot`.
// The kinds of row a cross-check gives: one per engine that gives equations
// at a state, and a "-mass" twin for each that compiles its own masses
// (simbody, mujoco, mujoco-mass, dart, bullet).
size_t rowKinds() {
  size_t n = 0;
  for (const EngineRow& r : engineRows()) n += (r.code.model ? 1 : 0) + (r.code.mass_note ? 1 : 0);
  return n;
}

void checkRows(const std::string& what, const CrossCheck& c, int states, double udot = kRoundOff) {
  REQUIRE(c.skipped.empty());
  REQUIRE(c.rows.size() == rowKinds() * (states + 1));
  for (const CrossCheckRow& row : c.rows) {
    INFO(what << " state " << row.state << " " << row.engine << ": A " << row.A << " B " << row.B << " u' " << row.udot);
    if (row.engine == "mujoco") {
      CHECK(row.A <= kMujocoRaw);
      CHECK(row.B <= kMujocoRaw);
      CHECK(row.udot <= 1e-6);
    } else {
      // An engine without a mass matrix (Bullet) gives A and B through its u': judged as u'.
      const bool from_udot = row.engine.find("-mass") == std::string::npos &&
                             engineCode(parseEngine(row.engine)).equations_note != nullptr;
      CHECK(row.A <= (from_udot ? udot : kRoundOff));
      CHECK(row.B <= (from_udot ? udot : kRoundOff));
      CHECK(row.udot <= udot);
    }
  }
}

}  // namespace

TEST_CASE("published robots: A, B and u' agree with MuJoCo's own URDF reading and with Simbody", "[crosscheck][urdf]") {
  const Robot robots[] = {{"ur5.urdf", {}}, {"z1.urdf", {}}, {"solo12.urdf", {}}, {"allegro_right_hand.urdf", {true, {}}}};
  for (const Robot& r : robots) {
    const Scene scene = loadScene(test::sourcePath(std::string("data/robots/") + r.file), r.options);
    checkRows(r.file, crossCheck(scene, r.options, 20, 3), 20);
  }
}

TEST_CASE("freed by --floating-base, published robots agree with MuJoCo's reading of a free root", "[crosscheck][urdf][sliding]") {
  // MuJoCo reads the URDF with a floating joint added to its root (its free
  // joint: world-frame linear, body-frame angular speed), Simbody the same Model.
  for (const char* file : {"solo12.urdf", "ur5.urdf", "z1.urdf"}) {
    UrdfOptions opt;
    opt.floating_base = true;
    const Scene scene = loadScene(test::sourcePath(std::string("data/robots/") + file), opt);
    REQUIRE(scene.model.bodies[0].joint.type == JointType::Free);
    checkRows(file, crossCheck(scene, opt, 20, 4), 20);
  }
}

TEST_CASE("a freed root gets a joint name apart from the URDF's, and a base that floats already is refused (floating-base)", "[crosscheck][urdf]") {
  // Unitree's A1 names a fixed joint floating_base: ours becomes floating_base_2, and MuJoCo's reading finds it.
  UrdfOptions opt;
  opt.floating_base = true;
  const Scene scene = loadScene(test::sourcePath("tests/robots/named_floating_base.urdf"), opt);
  REQUIRE(scene.model.bodies[0].joint.type == JointType::Free);
  CHECK(scene.model.bodies[0].joint.name == "floating_base_2");
  checkRows("named_floating_base.urdf", crossCheck(scene, opt, 20, 7), 20);
  // A massless root holding the base by a floating joint (Unitree's AS2): one line that says what to do.
  CHECK_THROWS_WITH(loadScene(test::sourcePath("tests/robots/floating_hub.urdf"), opt),
                    Catch::Contains("--floating-base: link 'space' (no mass) holds link 'hub' by the floating joint 'float' "
                                    "already: import without --floating-base"));
}

TEST_CASE("URDF prismatic and floating joints agree with MuJoCo's own reading", "[crosscheck][urdf][sliding]") {
  // tests/robots: a rail and a telescope with turned frames; a floating joint
  // whose frame is turned (MuJoCo's rest orientation composes with ours).
  for (const char* file : {"linear_axis.urdf", "floating_hub.urdf"}) {
    const Scene scene = loadScene(test::sourcePath(std::string("tests/robots/") + file), {});
    CHECK(scene.model.has_sliding);
    checkRows(file, crossCheck(scene, {}, 20, 5), 20);
  }
}

TEST_CASE("every shipped scene passes the cross-check against Simbody and MuJoCo", "[crosscheck]") {
  // Gimbals, balls, springs and dampers, slides and free joints all reach MuJoCo's MJCF.
  for (const std::string& name : test::dataScenes()) checkRows(name, crossCheck(test::sceneData(name), {}, 5, 6), 5, kUdotCond);
}

// Issue 54 item 5: an engine's row that takes a joint's speed map or its B
// from eigenmass's own code agrees with a bug there (the audit flipped the
// gimbal's axis rate: Simbody, MuJoCo and DART read 0.72 off in u', Bullet
// agreed to 1.5e-14), so such entries are named and their agreement is not counted.
TEST_CASE("crosscheck names the entries an engine takes from eigenmass's code and no others", "[crosscheck]") {
  const auto dependence = [](const std::string& scene) { return crossCheck(test::sceneData(scene), {}, 1, 1).dependent; };
  for (const std::string& name : test::dataScenes()) {  // Simbody and MuJoCo map every kind with their own kinematics
    INFO(name);
    const auto d = dependence(name);
    CHECK(d.count("simbody") == 0);
    CHECK(d.count("mujoco") == 0);
    CHECK(d.count("mujoco-mass") == 0);
    REQUIRE(d.count("bullet") == 1);
    CHECK(d.at("bullet").B == "B is A u' (Bullet exposes no right-hand side)");  // everywhere: it adds nothing to A and u'
  }
  // A slide and a hinge (cartpole, its slide sprung): Bullet's A and u' are its own, DART's spring part of B is ours.
  auto d = dependence("cartpole.json");
  CHECK(d.at("bullet").A.empty());
  CHECK(d.at("bullet").udot.empty());
  CHECK(d.at("dart").A.empty());
  CHECK_THAT(d.at("dart").B, Catch::StartsWith("its joint springs' and dampers' part"));
  CHECK(d.at("dart").udot.empty());
  // A gimbal root (pendulum5, no springs): Bullet's speed map is our kinematics; DART's every entry its own.
  d = dependence("pendulum5.json");
  CHECK_THAT(d.at("bullet").A, Catch::Contains("gimbal (body 'link1')") && Catch::Contains("eigenmass's joint kinematics"));
  CHECK(d.at("bullet").udot == d.at("bullet").A);
  CHECK(d.count("dart") == 0);
  // A free root and a sprung slide (floating_arm): DART's free-joint change of frame in B and u', its spring part in B.
  d = dependence("floating_arm.json");
  CHECK_THAT(d.at("bullet").A, Catch::Contains("free (body '"));
  CHECK(d.at("dart").A.empty());
  CHECK_THAT(d.at("dart").B, Catch::Contains("springs'") && Catch::Contains("free (body '"));
  CHECK_THAT(d.at("dart").udot, Catch::Contains("free (body '") && Catch::Contains("w x v"));
}

TEST_CASE("the cross-check reports an engine it cannot use instead of failing", "[crosscheck]") {
  // A 1e-16 kg body: valid here, below MuJoCo's smallest mass (mjMINVAL 1e-15), which its compiler refuses.
  SceneSpec s = parseSceneSpec(readFile(test::sourcePath("data/scenes/pendulum5.json"), "scene"));
  s.bodies.back().mass = 1e-16;
  Scene scene;
  scene.model = buildModel(s);
  scene.source.format = "eigenmass-scene/1";
  const CrossCheck c = crossCheck(scene, {}, 2, 1);
  REQUIRE(c.skipped.size() == 1);
  CHECK_THAT(c.skipped[0], Catch::StartsWith("mujoco: ") && Catch::Contains("mass"));
  CHECK(c.rows.size() == 3 * (rowKinds() - 2));  // the others (Simbody, DART) at the initial state and two random ones
}

TEST_CASE("DART's own URDF reading agrees with the import to round-off, and where it is not used a note says why", "[crosscheck][urdf][dart]") {
  // DART's loader (its own frames at the link origins, its own inertia
  // offsets): A, B and u' within round-off on published arms (measured at most
  // 5.7e-15, Z1's u'), the URDF's joint damping turned off as MuJoCo's is.
  for (const char* file : {"ur5.urdf", "z1.urdf", "solo12.urdf"}) {
    const Scene scene = loadScene(test::sourcePath(std::string("data/robots/") + file), {});
    const CrossCheck c = crossCheck(scene, {}, 10, 2);
    CHECK(c.notes.empty());
    for (const CrossCheckRow& row : c.rows)
      if (row.engine == "dart") CHECK(row.worst() <= kRoundOff);
  }
  // A free root (its reading's free joint sits at the root link's origin) and
  // inertias --balance-inertia changed: the Model built in DART, said once.
  UrdfOptions opt;
  opt.floating_base = true;
  const CrossCheck c = crossCheck(loadScene(test::sourcePath("data/robots/solo12.urdf"), opt), opt, 2, 2);
  REQUIRE(c.notes.size() == 1);
  CHECK_THAT(c.notes[0], Catch::StartsWith("dart: its own URDF reading is not used (its free root") &&
                             Catch::EndsWith("its rows are the imported Model built in dart"));
}

// A mechanism (docs/theory.md eq. (M7)): A and B are the tree's, u' the
// constrained one at states projected onto the loops; an engine that maps no
// mechanism is listed as skipped, never compared as the tree it would be.
// Simbody against the in-house multipliers: round-off times the conditioning
// of G A^-1 G^T (measured: Andrews 1.6e-12, A02 3.1e-13, A04 1.2e-13, the
// door and plate 2.9e-15). MuJoCo's closures are soft (its row's
// soft_closures): its A and B are judged (its point springs are tendons in
// B, its drives qfrc_applied), its u' is not (measured 0.097 to 0.79 off).
// DART's and Bullet's equations at a state are the tree's (their closures,
// point springs and drives act inside their steps: mechanism_state): A alone.
TEST_CASE("a mechanism's crosscheck compares the constrained u' at consistent random states", "[crosscheck][mechanism]") {
  constexpr double kConstrained = 1e-10;
  for (const char* file : {"data/scenes/mechanisms/andrews.json", "data/scenes/mechanisms/iftomm_a02_n2.json",
                           "data/scenes/mechanisms/iftomm_a04.json", "tests/scenes/mechanisms/door_and_plate.json"}) {
    INFO(file);
    const Scene scene = loadScene(test::sourcePath(file));
    const CrossCheck c = crossCheck(scene, {}, 20, 1);
    size_t mapped = 0, unmapped = 0;  // engines that give equations at a state, with and without a mechanism mapping
    for (Engine e : otherEngines())
      if (engineCode(e).model) (engineCode(e).mechanism_refusal ? mapped : unmapped) += 1;
    REQUIRE(mapped >= 4);  // Simbody, MuJoCo, DART, Bullet
    CHECK(c.rows.size() == 21 * mapped);
    for (const CrossCheckRow& row : c.rows) {
      INFO("state " << row.state << " " << row.engine << ": A " << row.A << " B " << row.B << " u' " << row.udot);
      const EngineCode& code = engineCode(parseEngine(row.engine));
      REQUIRE(code.mechanism_refusal);  // never an engine that would run the tree
      CHECK(row.A <= kRoundOff);
      CHECK(row.A_only == (code.mechanism_state != nullptr));  // DART's and Bullet's B and u' at a state are the tree's
      if (row.A_only) continue;
      CHECK(row.B <= kRoundOff);
      if (!code.soft_closures) CHECK(row.udot <= kConstrained);
    }
    CHECK(c.skipped.size() == unmapped);
    for (const std::string& s : c.skipped) CHECK_THAT(s, Catch::Contains("mechanism"));
  }
}

// The universal and slider closures (docs/theory.md §15): Simbody expresses
// them by its own constraints (Ball + ConstantAngle; PointOnLine +
// ConstantOrientation), so its constrained u' is an oracle our rows do not
// share. Measured: 3.2e-12 (RSUR), 8.2e-15 (slider-crank), 8.0e-16 (bead).
TEST_CASE("the universal and slider closures: Simbody's constrained u' equals ours at consistent random states", "[crosscheck][mechanism]") {
  constexpr double kConstrained = 1e-10;
  for (const char* file : {"tests/scenes/mechanisms/rsur_universal.json", "tests/scenes/mechanisms/slider_crank_closed.json",
                           "tests/scenes/mechanisms/bead_on_rail.json"}) {
    INFO(file);
    const CrossCheck c = crossCheck(loadScene(test::sourcePath(file)), {}, 20, 1);
    int simbody = 0;
    for (const CrossCheckRow& row : c.rows) {
      if (row.engine != "simbody") continue;
      ++simbody;
      INFO("state " << row.state << ": A " << row.A << " B " << row.B << " u' " << row.udot);
      CHECK(row.A <= kRoundOff);
      CHECK(row.B <= kRoundOff);
      CHECK(row.udot <= kConstrained);
    }
    CHECK(simbody == 21);
    for (const std::string& s : c.skipped) CHECK_THAT(s, Catch::Contains("closure, which") && Catch::Contains("cannot express"));
  }
}
