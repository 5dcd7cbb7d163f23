// What users bring, through the CLI as they run it (docs/plugins.md): the
// example plugin and a script's recorded run on scenes the project ships
// nowhere, and hostile plugins and CSVs, each one line and exit 2.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "app/cli_support.hpp"
#include "io/scene_json.hpp"

namespace {

namespace fs = std::filesystem;

std::string lib(const std::string& name) { return std::string(EM_BINARY_DIR) + "/lib/lib" + name + ".so"; }

std::string folder(const std::string& name) {
  const std::string d = std::string(EM_BINARY_DIR) + "/cli_outside/" + name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// A 4-link chain no file of the project holds: chain04 with its masses, levers and start changed.
std::string unseenScene(const std::string& dir) {
  em::SceneSpec s = em::test::chainSpec(4);
  s.name = "unseen4";
  for (size_t i = 0; i < s.bodies.size(); ++i) {
    s.bodies[i].mass = 0.7 + 0.3 * static_cast<double>(i);
    s.bodies[i].joint.in_body *= 1.2;
    if (i > 0) s.bodies[i].joint.axis[0] = em::Vec3(1, 0.4, -0.2 * static_cast<double>(i)).normalized();
  }
  s.t_end = 2;
  const std::string path = dir + "/unseen4.json";
  std::ofstream(path) << em::sceneJson(s);
  return path;
}

nlohmann::json readJson(const std::string& path) { return nlohmann::json::parse(std::ifstream(path)); }

}  // namespace

TEST_CASE("a plugin from outside on an unseen scene: crosscheck, compare, bench", "[cli][outside]") {
  const std::string d = folder("plugin"), s = unseenScene(d);
  const Run cc = eigenmass("crosscheck " + s + " --states 5 --plugin rnea=" + lib("rnea"));
  CHECK(cc.status == 0);
  CHECK_THAT(cc.out, Catch::Contains("rnea/simbody") && Catch::Contains("within 1e-07"));
  const Run c = eigenmass("compare " + s + " --methods classical --plugin rnea=" + lib("rnea") + " --out " + d + "/r.json --no-progress");
  REQUIRE(c.status == 0);
  const nlohmann::json r = readJson(d + "/r.json");
  const nlohmann::json& classical = r["methods"][0];
  const nlohmann::json& rnea = r["methods"][1];
  CHECK(rnea["name"] == "rnea");
  CHECK(rnea["source"]["plugin"] == lib("rnea"));
  // Under the same integrator the two formulations' trajectories agree to round-off grown over 2 s.
  CHECK(std::abs(rnea["max_pose_error_rad"].get<double>() - classical["max_pose_error_rad"].get<double>()) < 1e-9);
  CHECK(rnea["rhs_evals"] == classical["rhs_evals"]);
  const Run b = tool("eigenmass_bench", "4 --plugin rnea=" + lib("rnea"));
  CHECK(b.status == 0);
  CHECK_THAT(b.out, Catch::Contains("| rnea | / classical | u' diff |"));
}

TEST_CASE("a plugin on a mechanism: crosscheck judges its constrained u' against Simbody's, compare runs it with its loops closed", "[cli][outside][mechanism]") {
  // Bricard's A04: five hinges and a redundant hinge closure. The plugin
  // knows the tree alone; eigenmass closes the loop around it (eigenmass_plugin.h).
  const std::string d = folder("plugin_mechanism");
  const std::string s = em::test::sourcePath("data/scenes/mechanisms/iftomm_a04.json");
  const Run cc = eigenmass("crosscheck " + s + " --states 20 --plugin rnea=" + lib("rnea"));
  CHECK(cc.status == 0);
  CHECK(lineOf(cc.out, "rnea/simbody").size() > 0);
  CHECK(lineOf(cc.out, "rnea/dart").empty());  // DART's u' of a mechanism is not exposed: no row, not a tree's u' judged
  CHECK_THAT(cc.out, Catch::Contains("within 1e-07"));
  const Run c = eigenmass("compare " + s + " --methods classical --plugin rnea=" + lib("rnea") + " --t-end 0.5 --out " + d +
                          "/r.json --no-progress");
  REQUIRE(c.status == 0);
  const nlohmann::json r = readJson(d + "/r.json");
  const nlohmann::json& classical = r["methods"][0];
  const nlohmann::json& rnea = r["methods"][1];
  REQUIRE(rnea["name"] == "rnea");
  // The same formulation (projection) and steps: the two agree to round-off, and the report says how closed its loops stayed.
  CHECK(rnea["rhs_evals"] == classical["rhs_evals"]);
  CHECK(std::abs(rnea["max_pose_error_rad"].get<double>() - classical["max_pose_error_rad"].get<double>()) < 1e-12);
  CHECK(rnea["loops"]["formulation"] == "projection");
  CHECK(rnea["loops"]["max_position_violation_m"].get<double>() < 1e-12);
  CHECK(rnea["loops"]["projections"] == classical["loops"]["projections"]);
}

TEST_CASE("a script's body-pose run of an unseen scene: compare and plot", "[cli][outside]") {
  const std::string d = folder("script");
  const std::string csv = d + "/euler.csv";
  const std::string script = em::test::sourcePath("examples/recorded/euler_pendulum.py");
  REQUIRE(std::system(("/usr/bin/python3 " + script + " --dt 1e-3 --out " + csv).c_str()) == 0);
  const std::string s = em::test::sourcePath("examples/recorded/pendulum1.json");
  const Run c = eigenmass("compare " + s + " --methods classical --run euler=" + csv + " --out " + d + "/r.json --no-progress");
  REQUIRE(c.status == 0);
  const nlohmann::json r = readJson(d + "/r.json");
  const nlohmann::json& euler = r["methods"][1];
  CHECK(euler["source"]["format"] == "body-poses");
  CHECK(euler["source"]["declared"]["simulator"].get<std::string>().find("explicit Euler") != std::string::npos);
  CHECK(euler["integrator"] == "recorded");
  // Explicit Euler gains energy: (1 + h^2 w^2) per step, ~2.5 % over 2 s at h = 1 ms here (measured 3.6 %).
  CHECK(euler["energy_error_max"].get<double>() > 1e-2);
  CHECK(euler["divergence_time_s"]["1e-3"].is_number());
  const Run p = eigenmass("plot " + d + "/r.json --out " + d + "/figures", true);
  CHECK(p.status == 0);
  CHECK(fs::exists(d + "/figures/pendulum1-divergence.png"));
}

TEST_CASE("hostile plugins: one line naming the file, exit 2, before any run", "[cli][outside]") {
  const std::string d = folder("hostile"), s = scene("pendulum5.json");
  struct Case {
    std::string plugin, says;
  };
  const std::vector<Case> cases = {
      {"x=" + lib("hostile_nan"), "u' at the initial state is not finite"},
      {"x=" + lib("hostile_segv"), "crashed (SIGSEGV) in em_plugin_udot at t = 0"},
      {"x=" + lib("hostile_hang"), "no return within 0.5 s (killed)"},
      {"x=" + lib("hostile_abi"), "built against plugin ABI 101"},
      {"x=" + lib("hostile_nosym"), "no symbol em_plugin_udot"},
      {"x=" + lib("hostile_null"), "em_plugin_create returned NULL: this plugin refuses\\nevery \\x1b[31mmodel"},
      {"x=" + lib("hostile_error"), "returned an error at the initial state"},
      {"x=" + s, "not a loadable library"},
      {"x=/nonexistent/libx.so", "cannot read the plugin"},
      {lib("rnea"), "NAME=FILE expected"},
      {"classical=" + lib("rnea"), "a method of that name exists"},
  };
  for (const Case& c : cases) {
    const Run r = eigenmass("compare " + s + " --methods classical --plugin-timeout 0.5 --plugin " + c.plugin + " --out " + d +
                                "/r.json --no-progress", true);
    INFO(c.plugin << ": " << r.out);
    CHECK(r.status == 2);
    CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
    CHECK_THAT(r.out, Catch::StartsWith("eigenmass: error: --plugin: ") && Catch::Contains(c.says));
    CHECK_FALSE(fs::exists(d + "/r.json"));
  }
}

TEST_CASE("a plugin that crashes mid-run fails that run, the comparison goes on", "[cli][outside]") {
  const std::string d = folder("late");
  const Run r = eigenmass("compare " + scene("pendulum5.json") + " --t-end 1 --methods classical --plugin late=" +
                          lib("hostile_late_segv") + " --out " + d + "/r.json --no-progress");
  REQUIRE(r.status == 0);
  const nlohmann::json j = readJson(d + "/r.json");
  CHECK(j["methods"][0]["status"] == "ok");
  CHECK(j["methods"][1]["failure"]["kind"] == "plugin");
  CHECK(j["methods"][1]["failure"]["t"].get<double>() == Approx(0.25).margin(1e-3));
}

TEST_CASE("hostile recorded runs through the CLI: one line, exit 2", "[cli][outside]") {
  const std::string d = folder("csv"), s = scene("pendulum5.json");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"t,link1.q0\n", "line 1: column 'link1.q1' is missing"},
      {"t,bob.x\n", "line 1, column 2 ('bob.x'): scene 'pendulum5' has no body or joint 'bob'"},
      {"x,y\n", "line 1: the header's first column must be 't' (got 'x')"},
      // Issue 53 items 16 and 20: bytes from outside escaped; UTF-16 named; hex floats and a key said twice refused.
      {"t\x1b[31m,link1.q0\n", "line 1: the header's first column must be 't' (got 't\\x1b[31m')"},
      {std::string("\xff\xfet\0,\0", 6), "UTF-16 text (it starts with a UTF-16 byte-order mark): save it as UTF-8"},
      {std::string("t,x\n0\0,1\n", 10), "a NUL byte at line 2 (UTF-16 or binary, not text)"},
      {"# cpu_s: 1\n# cpu_s: 2\nt\n", "line 2: 'cpu_s' declared twice"},
  };
  for (const auto& [text, says] : cases) {
    std::ofstream(d + "/bad.csv") << text;
    const Run r = eigenmass("compare " + s + " --methods classical --run bad=" + d + "/bad.csv --out " + d + "/r.json", true);
    INFO(r.out);
    CHECK(r.status == 2);
    CHECK_THAT(r.out, Catch::StartsWith("eigenmass: error: --run: " + d + "/bad.csv: " + says));
    CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
  }
  // An output onto the run's own file is refused: inputs are never overwritten.
  std::ofstream(d + "/mine.csv") << "t\n";
  const Run r = eigenmass("compare " + s + " --methods classical --run mine=" + d + "/mine.csv --out " + d + "/mine.csv", true);
  CHECK(r.status == 2);
}

// Issue 53, bug 3: SIGINT or SIGTERM to the parent left a hung plugin's child spinning under PID 1.
TEST_CASE("a plugin's child does not outlive eigenmass when it is interrupted", "[cli][outside]") {
  const std::string d = folder("orphan");
  for (const char* sig : {"TERM", "INT"}) {
    // The child probes a plugin that never returns (a timeout of 60 s: only the signal ends it); find it, signal the
    // parent, then the child must be gone within 2 s (it is killed with its parent, and reaped by init).
    const std::string script =
        std::string(EM_BINARY_DIR) + "/bin/eigenmass compare " + scene("pendulum5.json") +
        " --methods classical --plugin-timeout 60 --plugin h=" + lib("hostile_hang") + " --out " + d + "/r.json --no-progress "
        ">/dev/null 2>&1 & P=$!; C=; for i in $(seq 100); do C=$(pgrep -P $P); [ -n \"$C\" ] && break; sleep 0.05; done; "
        "[ -n \"$C\" ] || { kill -9 $P; exit 3; }; kill -" + sig + " $P; wait $P; "
        "for i in $(seq 40); do kill -0 $C 2>/dev/null || exit 0; sleep 0.05; done; kill -9 $C; exit 4";
    const int st = std::system(("bash -c '" + script + "'").c_str());
    INFO("SIG" << sig << ": 3 = no child seen, 4 = the child outlived its parent");
    CHECK(WEXITSTATUS(st) == 0);
  }
}

// Issue 53 item 20: a plugin's stdout was mixed into eigenmass's, its last buffer lost.
TEST_CASE("a plugin's printing goes to standard error, every byte of it, never into eigenmass's standard output", "[cli][outside]") {
  const std::string d = folder("print");
  const Run r = eigenmass("simulate " + scene("pendulum5.json") + " --t-end 0.1 --plugin p=" + lib("hostile_print") + " --out " + d +
                              "/run.csv --no-progress",
                          false, d + "/stdout.txt");
  REQUIRE(r.status == 0);
  std::ifstream in(d + "/stdout.txt");
  const std::string out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(out.find("the plugin talks") == std::string::npos);
  // Once per child that created it: the probe and the run.
  size_t said = 0;
  for (size_t at = r.out.find("the plugin talks on stdout"); at != std::string::npos; at = r.out.find("the plugin talks on stdout", at + 1)) ++said;
  CHECK(said == 2);
}
