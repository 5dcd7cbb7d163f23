// Sweeps: the plan format and its one-line errors, the cases a plan expands
// to, the pieces of the tables, and the command run both ways (local worker
// processes, GNU parallel over --list) giving the same merged results.
#include <regex>

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <fstream>
#include <sstream>

#include "reference/engine.hpp"
#include "sweep/sweep.hpp"
#include "support.hpp"

using namespace em;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::string kDir = std::string(EM_BINARY_DIR) + "/sweep-tests";

json smallPlan() {
  return {{"format", "eigenmass-plan/1"},
          {"name", "small"},
          {"scenes", {test::sourcePath("data/scenes/pendulum5.json"), test::sourcePath("data/scenes/chain02.json")}},
          {"t_end", 0.5},
          {"reference", {{"method", "classical"}, {"integrator", "rk8pd"}, {"tolerance", 1e-12}}},
          {"lines", {{{"methods", {"classical", "eigen"}}, {"integrator", "rk4"}, {"dt", {1e-2, 5e-3}}},
                     {{"methods", {"simbody"}}, {"integrator", "rkmerson"}, {"tolerance", {1e-6}}}}},
          {"tables", {"work-precision"}}};
}

std::string writePlan(const json& plan, const std::string& name) {
  fs::create_directories(kDir);
  const std::string path = kDir + "/" + name;
  std::ofstream(path) << plan.dump(1);
  return path;
}

// The one-line error loadPlan gives for `plan` ("" if it loads).
std::string planError(const json& plan) {
  try {
    loadPlan(writePlan(plan, "bad.json"));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

int shell(const std::string& cmd) { return WEXITSTATUS(std::system(cmd.c_str())); }

std::string eigenmass() { return std::string(EM_BINARY_DIR) + "/bin/eigenmass"; }

// The merged CSV's rows with the timing columns (cpu_*) dropped.
std::vector<std::vector<std::string>> withoutTimings(const std::string& csv_path) {
  std::ifstream in(csv_path);
  std::vector<std::vector<std::string>> rows;
  std::vector<bool> keep;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> cells, kept;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (line.back() == ',') cells.push_back("");
    if (keep.empty())
      for (const std::string& c : cells) keep.push_back(c.rfind("cpu_", 0) != 0);
    for (size_t i = 0; i < cells.size() && i < keep.size(); ++i)
      if (keep[i]) kept.push_back(cells[i]);
    rows.push_back(kept);
  }
  return rows;
}

}  // namespace

TEST_CASE("a plan expands to its references first, then scene x line x method x setting, with stable names", "[sweep]") {
  const Plan p = loadPlan(writePlan(smallPlan(), "small.json"));
  const std::vector<SweepCase> cases = planCases(p);
  REQUIRE(cases.size() == 2 + 2 * (2 * 2 + 1));
  CHECK(cases[0].name == "pendulum5.reference");
  CHECK(cases[1].name == "chain02.reference");
  CHECK(cases[2].name == "pendulum5.classical.rk4.0.01");
  CHECK(cases[3].name == "pendulum5.classical.rk4.0.005");
  CHECK(cases[4].name == "pendulum5.eigen.rk4.0.01");
  CHECK(cases[6].name == "pendulum5.simbody.rkmerson.1e-06");
  CHECK(cases[7].scene_name == "chain02");
  for (const SweepCase& c : cases) {
    CHECK(c.spec->t_end == 0.5);
    CHECK(c.spec->output_dt == 0.01);
  }
  CHECK(p.repeats == 3);
}

TEST_CASE("a line's method that cannot run a scene is left out there and said, not run to an error", "[sweep][mechanism]") {
  // The engine study's template runs the engines' u' under our integrators;
  // on a mechanism those are a tree's (methodRefusal). Before, each such case
  // ended in an error and the study called itself incomplete.
  useEngines();
  json plan = smallPlan();
  plan["scenes"] = {test::sourcePath("data/scenes/pendulum5.json"), test::sourcePath("data/scenes/mechanisms/iftomm_a04.json")};
  plan["lines"] = {{{"methods", {"classical", "mujoco-udot", "dart-udot"}}, {"integrator", "rk4"}, {"dt", {1e-2, 5e-3}}}};
  const Plan p = loadPlan(writePlan(plan, "left_out.json"));
  std::map<std::string, int> per_scene_method;
  for (const SweepCase& c : planCases(p))
    if (c.role == CaseRole::Run) ++per_scene_method[c.scene_name + " " + methodName(c.spec->method)];
  CHECK(per_scene_method["pendulum5 mujoco-udot"] == 2);  // a tree: run
  CHECK(per_scene_method["iftomm_a04 classical"] == 2);
  CHECK(per_scene_method.count("iftomm_a04 mujoco-udot") == 0);
  CHECK(per_scene_method.count("iftomm_a04 dart-udot") == 0);
  const std::string said = leftOutLines(p);
  CHECK(said.find("**Not run on iftomm_a04** (4 cases of the plan's lines left out): mujoco-udot, dart-udot: its u' comes from "
                  "outside the formation") == 0);
  CHECK(said.find("pendulum5") == std::string::npos);
}

TEST_CASE("a bad plan is refused in one line naming the file and the key", "[sweep][hostile]") {
  json p = smallPlan();
  p["lines"][0]["dt"][1] = -1;
  CHECK_THAT(planError(p), Catch::Contains("bad.json: lines[0].dt[1]: must be a finite number > 0"));
  p = smallPlan();
  p["lines"][1]["methods"][0] = "classical";
  CHECK_THAT(planError(p), Catch::Contains("bad.json: lines[1].methods[0]:"));
  p = smallPlan();
  p["lines"][0]["tolerance"] = {1e-6};
  CHECK_THAT(planError(p), Catch::Contains("lines[0].tolerance: rk4 takes dt, not tolerance"));
  p = smallPlan();
  p["repeats"] = 2;
  CHECK_THAT(planError(p), Catch::Contains("repeats: must be a whole number from 3"));
  p = smallPlan();
  p["scenes"][1] = "no-such.json";
  CHECK_THAT(planError(p), Catch::Contains("scenes[1]: no such file"));
  p = smallPlan();
  p["scenes"][1] = p["scenes"][0];
  CHECK_THAT(planError(p), Catch::Contains("scenes[1]: a second scene named 'pendulum5'"));
  p = smallPlan();
  p["t_ned"] = 1;
  CHECK_THAT(planError(p), Catch::Contains("t_ned: unknown key"));
  // Blamed on what is wrong (issue 42): the plan's own grid, not its reference; a scene given as a plan.
  p = smallPlan();
  p["output_dt"] = 0.3;
  CHECK_THAT(planError(p), Catch::Contains("bad.json: t_end: ") && Catch::Contains("must be a whole multiple of output_dt 0.3"));
  p = parseJsonStrict(readFile(test::sourcePath("data/scenes/pendulum5.json"), "scene"));
  CHECK_THAT(planError(p), Catch::Contains("bad.json: format: a scene, not a plan"));
  p = smallPlan();
  p["lines"][0]["dt"][0] = 3e-3;  // does not divide the 0.01 s output grid
  CHECK_THAT(planError(p), Catch::Contains("bad.json: lines: pendulum5.classical.rk4.0.003:"));
  p = smallPlan();
  p.erase("reference");
  CHECK_THAT(planError(p), Catch::Contains("tables: work-precision needs a reference"));
  p = smallPlan();
  p["refine"] = 1.5;
  CHECK_THAT(planError(p), Catch::Contains("bad.json: refine: must be a whole number from 0 to 10"));
  p["refine"] = 11;
  CHECK_THAT(planError(p), Catch::Contains("bad.json: refine: must be a whole number from 0 to 10"));
  p = smallPlan();  // issue 53 item 13: refine_tol is read only under refine > 0
  p["refine_tol"] = 1e-3;
  CHECK_THAT(planError(p), Catch::Contains("bad.json: refine_tol: read only with refine > 0, and refine is 0"));
  p["refine"] = 2;
  CHECK(planError(p).empty());
  p = smallPlan();  // an ensemble: its count, its perturbation, its keys, each named
  p["ensemble"] = {{"count", 0}, {"perturb", {{"q", 1e-3}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: ensemble.count: must be a whole number from 1"));
  p["ensemble"] = {{"count", 5}, {"perturb", {{"q", 0}, {"u", 0}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: ensemble.perturb: q or u must be > 0"));
  p["ensemble"] = {{"count", 5}, {"perturb", {{"q", -1e-3}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: ensemble.perturb.q: must be a finite number >= 0"));
  p["ensemble"] = {{"count", 5}, {"perturb", {{"q", 1e6}}}};  // issue 42, bug 11: a member ran at 2.5e6 rad
  CHECK_THAT(planError(p), Catch::Contains("bad.json: ensemble.perturb.q: 1e+06 beyond 1 rad (m)"));
  p["ensemble"] = {{"count", 5}, {"perturb", {{"u", 1e300}}}};  // issue 53 item 12: a raw type_error, exit 1, at 1e300
  CHECK_THAT(planError(p), Catch::Contains("bad.json: ensemble.perturb: scene pendulum5: a member may reach u link1.u0: speed 8.6e+300 "
                                           "rad/s beyond +-1e+06 rad/s (members lie within 8.6 sigma"));
  {  // issue 53 item 12: q0 = 9999.9 and perturb.q = 1 ran members at 10002.7 rad, past the bound the scene is held to
    json edge = parseJsonStrict(readFile(test::sourcePath("data/scenes/pendulum5.json"), "scene"));
    edge["bodies"][0]["joint"]["q0"][0] = 9999.9;
    fs::create_directories(kDir);
    std::ofstream(kDir + "/edge.json") << edge.dump(1);
    json q = smallPlan();
    q["scenes"] = {kDir + "/edge.json"};
    q["ensemble"] = {{"count", 5}, {"perturb", {{"q", 1}}}};
    CHECK_THAT(planError(q), Catch::Contains("bad.json: ensemble.perturb: scene edge: a member may reach q link1.q0: angle 10008.5 rad "
                                             "beyond +-10000 rad"));
    q["ensemble"]["perturb"]["q"] = 1e-3;  // 9999.9 + 8.6e-3: within
    CHECK(planError(q).empty());
  }
  p["ensemble"] = {{"count", 5}, {"perturb", {{"w", 1e-3}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: ensemble.perturb.w: unknown key"));
  // A claim the figures mark: within t_end, a printable label.
  p["ensemble"] = {{"count", 5}, {"perturb", {{"q", 1e-3}}}, {"claim", {{"t_s", 1e3}, {"label", "x"}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: ensemble.claim.t_s: 1000 beyond the plan's t_end"));
  p["ensemble"]["claim"] = {{"t_s", 0.1}, {"label", "two\nlines"}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: ensemble.claim.label: 1 to 80 characters without a control character"));
  p["ensemble"]["claim"] = {{"t_s", 0.1}, {"label", "x"}, {"source", "y"}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: ensemble.claim.source: unknown key"));
  p["ensemble"] = {{"count", 5}, {"perturb", {{"q", 1e-3}}}};
  p["repeats"] = 1;  // an ensemble may run each case once; a plain plan may not (above)
  CHECK(planError(p).empty());
  p = smallPlan();  // every row option is a plan key under its name, checked by its row's range
  p["block_gap"] = 2;
  CHECK_THAT(planError(p), Catch::Contains("bad.json: block_gap: must be in (0, 1], got 2"));
  p["block_gap"] = 0.1;
  CHECK(planError(p).empty());
  p = smallPlan();  // beyond the budgets: the hint is the plan's keys, not a flag sweep does not take
  p["t_end"] = 1e7;
  CHECK_THAT(planError(p), Catch::Contains("1e+09 samples, more than the budget of 1e+06 (the plan keys max_steps and max_samples raise the budgets)") &&
                               !Catch::Contains("--allow-long-run"));
  p["max_samples"] = 1e10;  // then the steps' budget speaks
  CHECK_THAT(planError(p), Catch::Contains("steps, more than the budget of 1e+08 (the plan keys max_steps and max_samples"));
  p = smallPlan();  // what becomes a file name, a shell command or a CSV field keeps to the scene-name rule
  p["name"] = "two\nlines";
  CHECK_THAT(planError(p), Catch::Contains("bad.json: name: must be letters, digits"));
  p["name"] = "esc\x1b[31m";
  CHECK_THAT(planError(p), Catch::Contains("bad.json: name: must be letters, digits"));
  p = smallPlan();
  p["description"] = "a\nb";
  CHECK_THAT(planError(p), Catch::Contains("bad.json: description: a control character"));
  p = smallPlan();
  fs::copy_file(test::sourcePath("data/scenes/chain02.json"), kDir + "/a,\"b.json", fs::copy_options::overwrite_existing);
  p["scenes"][1] = "a,\"b.json";
  CHECK_THAT(planError(p), Catch::Contains("bad.json: scenes[1]: the file's stem must be letters, digits"));
  p = smallPlan();
  p["reference"]["dt"] = 1e-3;  // beside its tolerance: one of them would be dropped
  CHECK_THAT(planError(p), Catch::Contains("bad.json: reference.dt:") && Catch::Contains("takes tolerance, not dt"));
  CHECK(planError(smallPlan()).empty());
}

TEST_CASE("time to reach an error is interpolated log-log between the bracketing points", "[sweep]") {
  bool at_first = false;
  const std::vector<double> cpu = {1, 2, 4}, err = {1e-2, 1e-4, 1e-6};
  CHECK(timeToReach(cpu, err, 1e-3, at_first).value() == Approx(std::sqrt(2.0)).epsilon(1e-14));
  CHECK_FALSE(at_first);
  CHECK(timeToReach(cpu, err, 1e-1, at_first).value() == 1);
  CHECK(at_first);
  CHECK_FALSE(timeToReach(cpu, err, 1e-7, at_first));
  // A failed point (infinite error) is never interpolated across.
  CHECK(timeToReach({1, 2}, {INFINITY, 1e-4}, 1e-3, at_first).value() == 2);
}

TEST_CASE("the log-log slope of a power law is its exponent", "[sweep]") {
  const std::vector<double> dt = {1e-2, 5e-3, 2.5e-3, 1.25e-3};
  std::vector<double> err;
  for (double h : dt) err.push_back(3 * std::pow(h, 4));
  CHECK(logSlope(dt, err).value() == Approx(4).epsilon(1e-12));
  CHECK_FALSE(logSlope({1}, {1}));
}

TEST_CASE("sweep in process and through GNU parallel give the same merged results, classical rk4 shows order 4",
          "[sweep][cli]") {
  const std::string plan = test::sourcePath("data/plans/order-check.json");
  const std::string a = kDir + "/inprocess", b = kDir + "/parallel";
  fs::remove_all(a);
  fs::remove_all(b);
  REQUIRE(shell(eigenmass() + " sweep " + plan + " --results " + a + " -j 2 >/dev/null 2>&1") == 0);
  REQUIRE(shell("command -v parallel >/dev/null") == 0);  // Debian's `parallel` (./run installs it)
  REQUIRE(shell(eigenmass() + " sweep " + plan + " --list --results " + b + " | parallel --will-cite -j 2 >/dev/null") == 0);
  REQUIRE(shell(eigenmass() + " sweep " + plan + " --merge " + b + " >/dev/null") == 0);
  const auto ra = withoutTimings(a + "/order-check.csv"), rb = withoutTimings(b + "/order-check.csv");
  REQUIRE(ra.size() == 1 + 12);
  CHECK(ra == rb);
  // Observed order of classical rk4 from the merged CSV: max coordinate error against dt.
  std::vector<double> dt, err;
  for (const auto& row : ra)
    if (row[3] == "classical" && row[4] == "rk4") dt.push_back(std::stod(row[6])), err.push_back(std::stod(row[11]));
  REQUIRE(dt.size() == 4);
  const double order = logSlope(dt, err).value();
  INFO("observed order " << order);
  CHECK(std::fabs(order - 4) <= 0.3);
}

TEST_CASE("a sweep resumes without rerunning a case, and refuses a result made by another plan", "[sweep][cli]") {
  json p = smallPlan();
  p["t_end"] = 0.1;
  p["lines"] = {{{"methods", {"classical"}}, {"integrator", "rk4"}, {"dt", {1e-2}}}};
  const std::string plan = writePlan(p, "resume.json"), dir = kDir + "/resume";
  fs::remove_all(dir);
  REQUIRE(shell(eigenmass() + " sweep " + plan + " --results " + dir + " -j 1 >/dev/null 2>&1") == 0);
  const std::string one = dir + "/pendulum5.classical.rk4.0.01.json";
  const auto written = fs::last_write_time(one);
  REQUIRE(shell(eigenmass() + " sweep " + plan + " --results " + dir + " -j 1 >/dev/null 2>&1") == 0);
  CHECK(fs::last_write_time(one) == written);
  {  // Issue 53 item 18: a merge with cases missing says so on the page itself, not only on stderr.
    const std::string part = kDir + "/resume-part";
    fs::remove_all(part);
    fs::copy(dir, part);
    fs::remove(part + "/pendulum5.classical.rk4.0.01.json");
    CHECK(shell(eigenmass() + " sweep " + plan + " --merge " + part + " >/dev/null 2>&1") == 1);
    CHECK(readFile(part + "/small.md", "tables").find("**Incomplete: 1 of 4 cases have no result in this folder (the first: "
                                         "pendulum5.classical.rk4.0.01). The tables cover the 3 that do") != std::string::npos);
  }
  {  // A merged output linked to a case file the merge reads is refused, naming it (a hostile pass: the merged
     // CSV was written into the reference's case file through the link, destroying it).
    const std::string linked = kDir + "/resume-linked";
    fs::remove_all(linked);
    fs::copy(dir, linked);
    fs::remove(linked + "/small.csv");
    fs::create_symlink("pendulum5.reference.json", linked + "/small.csv");
    const std::string before = readFile(linked + "/pendulum5.reference.json", "case");
    const std::string lerr = kDir + "/resume-linked.err";
    CHECK(shell(eigenmass() + " sweep " + plan + " --merge " + linked + " >/dev/null 2>" + lerr) == 2);
    CHECK_THAT(readFile(lerr, "stderr"), Catch::Contains("small.csv, which is an input file; refusing to overwrite it"));
    CHECK(readFile(linked + "/pendulum5.reference.json", "case") == before);
  }
  p["t_end"] = 0.2;
  const std::string other = writePlan(p, "resume2.json");
  const std::string err = kDir + "/resume.err";
  CHECK(shell(eigenmass() + " sweep " + other + " --results " + dir + " >/dev/null 2>" + err) == 2);
  std::ifstream in(err);
  std::string line;
  std::getline(in, line);
  CHECK_THAT(line, Catch::Contains("reference.json: made by another plan"));
  // The field that differs and both values, in a short line (issue 42: it was two whole keys, 700 characters).
  CHECK_THAT(line, Catch::Contains("(its t_end is 0.1, this plan's 0.2)"));
  CHECK(line.size() < 300);
  CHECK(fs::last_write_time(one) == written);
}

TEST_CASE("a plan sweeps robots with their import options: the Allegro hand with balance_inertia", "[sweep][cli][urdf]") {
  // The hand violates the triangle inequality (docs/urdf.md): as a plain path it is
  // refused naming the plan's key that repairs it, not the CLI's flag; with the
  // option it runs, and the option is part of every case's key.
  const std::string hand = test::sourcePath("data/robots/allegro_right_hand.urdf");
  json p = smallPlan();
  p["name"] = "hand";
  p["t_end"] = 0.05;
  p["scenes"] = {hand};
  p["lines"] = {{{"methods", {"classical", "articulated"}}, {"integrator", "rk4"}, {"dt", {1e-3}}}};
  const std::string plain = planError(p);
  CHECK_THAT(plain, Catch::Contains("scenes[0]") && Catch::Contains("\"balance_inertia\": true") &&
                        !Catch::Contains("--balance-inertia"));
  p["scenes"] = {{{"file", hand}, {"balance_inertia", true}, {"lock_joint", {"joint_0.0"}}}};
  const Plan plan = loadPlan(writePlan(p, "hand.json"));
  REQUIRE(plan.scenes.size() == 1);
  CHECK(plan.scenes[0].urdf.balance_inertia);
  CHECK(plan.scenes[0].urdf.lock_joints == std::vector<std::string>{"joint_0.0"});
  const std::string dir = kDir + "/hand";
  fs::remove_all(dir);
  REQUIRE(shell(eigenmass() + " sweep " + kDir + "/hand.json --results " + dir + " -j 1 >/dev/null 2>&1") == 0);
  std::ifstream in(dir + "/allegro_right_hand.articulated.rk4.0.001.json");
  const json c = json::parse(in);
  CHECK(c["key"]["scene_import"]["balance_inertia"] == true);
  CHECK(c["result"]["status"] == "ok");
  CHECK(c["result"]["nu"] == 15);  // 16 joints, one locked
  CHECK(c["result"]["max_pose_error_rad"].get<double>() < 1e-6);  // against classical rk8pd 1e-12 over 0.05 s
  // Options a JSON scene cannot take, keys a scene entry does not have, a wrong type: one line each.
  p["scenes"] = {{{"file", test::sourcePath("data/scenes/pendulum5.json")}, {"floating_base", true}}};
  CHECK_THAT(planError(p), Catch::Contains("scenes[0]: import options apply to URDF files only"));
  p["scenes"] = {{{"file", hand}, {"balance", true}}};
  CHECK_THAT(planError(p), Catch::Contains("scenes[0].balance: unknown key"));
  p["scenes"] = {{{"file", hand}, {"balance_inertia", "yes"}}};
  CHECK_THAT(planError(p), Catch::Contains("scenes[0].balance_inertia: expected true or false"));
  p["scenes"] = {{{"file", hand}, {"balance_inertia", true}, {"lock_joint", {"nope"}}}};
  CHECK_THAT(planError(p), Catch::Contains("scenes[0]") && Catch::Contains("no joint named 'nope'"));
  // start_offset (issue 54 item 2): its seed is asked for, its sigmas bounded, loops refused; one line each.
  p["scenes"] = {{{"file", hand}, {"balance_inertia", true}, {"start_offset", {{"q", 0.3}}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: scenes[0].start_offset.seed: missing"));
  p["scenes"] = {{{"file", hand}, {"balance_inertia", true}, {"start_offset", {{"q", 2}, {"seed", 1}}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: scenes[0].start_offset.q: 2 beyond 1 rad (m)"));
  p["scenes"] = {{{"file", hand}, {"balance_inertia", true}, {"start_offset", {{"u", 1e3}, {"seed", 1}}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: scenes[0].start_offset.u: 1000 beyond 100 rad/s (m/s)"));
  p["scenes"] = {{{"file", hand}, {"balance_inertia", true}, {"start_offset", {{"q", 0}, {"seed", 1}}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: scenes[0].start_offset: q or u must be > 0"));
  p["scenes"] = {{{"file", hand}, {"balance_inertia", true}, {"start_offset", {{"q", 0.1}, {"seed", 1}, {"sed", 1}}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: scenes[0].start_offset.sed: unknown key"));
  p["scenes"] = {{{"file", test::sourcePath("data/scenes/mechanisms/andrews.json")}, {"start_offset", {{"q", 0.1}, {"seed", 1}}}}};
  CHECK_THAT(planError(p), Catch::Contains("bad.json: scenes[0].start_offset: the scene has loops"));
  // Run: every case starts where the file says (the displaced start, by name), and the offset is in the key.
  p["scenes"] = {{{"file", hand}, {"balance_inertia", true}, {"start_offset", {{"q", 0.3}, {"seed", 2}}}}};
  const Plan off = loadPlan(writePlan(p, "hand_off.json"));
  REQUIRE(off.scenes[0].start_offset);
  CHECK(off.scenes[0].start_offset->seed == 2);
  const std::string odir = kDir + "/hand_off";
  fs::remove_all(odir);
  REQUIRE(shell(eigenmass() + " sweep " + kDir + "/hand_off.json --results " + odir + " -j 1 >/dev/null 2>&1") == 0);
  std::ifstream oin(odir + "/allegro_right_hand.articulated.rk4.0.001.json");
  const json o = json::parse(oin);
  CHECK(o["key"]["start_offset"] == json({{"q", 0.3}, {"u", 0.0}, {"seed", 2}}));
  double displaced = 0;  // q = 0 in the file; sigma 0.3 rad over 16 joints
  for (const auto& [name, q] : o["start"]["q0"].items()) displaced = std::max(displaced, std::abs(q.get<double>()));
  CHECK(displaced > 0.05);
  std::ifstream rin(odir + "/allegro_right_hand.reference.json");
  const json ref = json::parse(rin);
  CHECK(ref["start"] == o["start"]);  // the reference starts there too
  CHECK(ref["result"]["sensitivity_twin_max_pose_rad"].is_number());
  // One file at two starts (issue 75, item 3: the hand over several starts): each entry named; a name
  // twice, or one that cannot name files, refused in one line.
  p["scenes"] = {{{"file", hand}, {"name", "hand_seed1"}, {"balance_inertia", true}, {"start_offset", {{"q", 0.3}, {"seed", 1}}}},
                 {{"file", hand}, {"name", "hand_seed2"}, {"balance_inertia", true}, {"start_offset", {{"q", 0.3}, {"seed", 2}}}}};
  const Plan two = loadPlan(writePlan(p, "hand_two.json"));
  REQUIRE(two.scenes.size() == 2);
  CHECK(two.scenes[1].stem() == "hand_seed2");
  CHECK(planCases(two).front().name.rfind("hand_seed1.", 0) == 0);
  p["scenes"][1]["name"] = "hand_seed1";
  CHECK_THAT(planError(p), Catch::Contains("bad.json: scenes[1]: a second scene named 'hand_seed1'"));
  p["scenes"][1]["name"] = "../up";
  CHECK_THAT(planError(p), Catch::Contains("bad.json: scenes[1].name: must be letters, digits"));
  p["scenes"][0].erase("name");
  p["scenes"][1].erase("name");
  CHECK_THAT(planError(p), Catch::Contains("bad.json: scenes[1]: a second scene named 'allegro_right_hand'"));
}

TEST_CASE("a plan names a plugin and a recorded run: their cases equal classical's", "[sweep][cli][outside]") {
  // The oracle is classical itself: the example plugin computes the same u' by
  // Newton-Euler (its trajectory under rk4 agrees to ~1e-12), and the recorded
  // run is classical's own run written out by `simulate` and read back.
  const std::string dir = kDir + "/outside";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string scene = test::sourcePath("data/scenes/pendulum5.json");
  REQUIRE(shell(eigenmass() + " simulate " + scene + " --t-end 0.5 --dt 1e-3 --out " + dir + "/mine.csv --no-progress >/dev/null") == 0);
  json p = {{"format", "eigenmass-plan/1"},
            {"name", "outside"},
            {"scenes", {scene}},
            {"t_end", 0.5},
            {"reference", {{"method", "classical"}, {"integrator", "rk8pd"}, {"tolerance", 1e-12}}},
            {"plugins", {{"rnea", std::string(EM_BINARY_DIR) + "/lib/librnea.so"}}},
            {"runs", {{"mine", "mine.csv"}}},  // against the plan's folder
            {"lines", {{{"methods", {"classical", "rnea"}}, {"integrator", "rk4"}, {"dt", {1e-3}}}}}};
  std::ofstream(dir + "/plan.json") << p.dump(1);
  REQUIRE(shell(eigenmass() + " sweep " + dir + "/plan.json --results " + dir + "/results -j 1 >/dev/null 2>&1") == 0);
  const auto rows = withoutTimings(dir + "/results/outside.csv");
  REQUIRE(rows.size() == 1 + 4);  // the reference, classical, rnea, mine
  std::map<std::string, std::vector<std::string>> by;
  for (const auto& r : rows) by[r[3]] = r;
  REQUIRE(by.count("mine"));
  CHECK(by["mine"][4] == "recorded");
  CHECK(by["mine"][7] == "ok");
  CHECK(by["mine"][10] == by["classical"][10]);  // the pose error, to the printed digit
  CHECK(std::abs(std::stod(by["rnea"][10]) - std::stod(by["classical"][10])) < 1e-11);
  // What a plan may not do with a run file: one line naming the key.
  p["scenes"].push_back(test::sourcePath("data/scenes/chain02.json"));
  CHECK_THAT(planError(p), Catch::Contains("runs: a recorded run is of one scene; this plan has 2"));
  p["scenes"].erase(1);
  p["runs"]["bad"] = "nowhere.csv";
  CHECK_THAT(planError(p), Catch::Contains("runs.bad: ") && Catch::Contains("cannot open the recorded run"));
}

TEST_CASE("docs/sweep.md's case counts are the shipped plans' own", "[sweep][docs]") {
  // Issue 53 item 20: the page said 49, 636 and 31 where the plans had 56, 894 and 60.
  const std::string page = readFile(test::sourcePath("docs/sweep.md"), "docs");
  const std::vector<std::pair<std::string, std::string>> plans = {
      {"`work-precision.json`", "work-precision.json"}, {"`cost-vs-size.json`", "cost-vs-size.json"},
      {"`eigen-block.json`", "eigen-block.json"},       {"`paper-ensemble.json`", "paper-ensemble.json"},
      {"`sigma/paper-sigma-{1e-6,1e-4,1e-2}.json`", "sigma/paper-sigma-1e-6.json"}, {"`engines.json`", "engines.json"},
      {"`fourbar-size.json`", "fourbar-size.json"}};
  for (const auto& [named, file] : plans) {
    INFO(named);
    const size_t at = page.find(named);
    REQUIRE(at != std::string::npos);
    const std::string after = page.substr(at, 400);
    std::smatch m;
    REQUIRE(std::regex_search(after, m, std::regex("([0-9]+) cases")));
    CHECK(std::stoul(m[1].str()) == planCases(loadPlan(test::sourcePath("data/plans/" + file))).size());
  }
}

TEST_CASE("a line's tuning sets are routes of their own: named, applied, recorded, refused where no method reads them",
          "[sweep][mechanism][cli]") {
  // Issue 76: every owner at its best settings. A set is one case per method and setting, its options applied
  // to that run alone; the same method untuned is another route.
  useEngines();
  json plan = smallPlan();
  plan["name"] = "tuned";
  plan["scenes"] = {test::sourcePath("data/scenes/mechanisms/iftomm_a04.json")};
  plan["t_end"] = 1;
  plan["output_dt"] = 0.01;
  plan["lines"] = {{{"methods", {"mujoco"}}, {"integrator", "rk4"}, {"dt", {1e-3}}},
                   {{"methods", {"mujoco"}}, {"integrator", "rk4"}, {"dt", {1e-3}},
                    {"tuning", {{{"mujoco_solref_time", 0.005}}, {{"mujoco_solref_time", 0.1}, {"mujoco_solref_damping", 2}}}}},
                   {{"methods", {"classical"}}, {"formulations", {"augmented-lagrangian"}}, {"integrator", "trapezoidal"},
                    {"dt", {1e-2}}, {"tuning", {{{"al_penalty_ratio", 1e6}}}}}};
  plan["tables"] = {"runs"};
  {  // a method of the line that reads no set runs once, untuned (classical beside mujoco's sets)
    json both = plan;
    both["lines"][1]["methods"] = {"mujoco", "classical"};
    int untuned = 0;
    for (const SweepCase& c : planCases(loadPlan(writePlan(both, "both.json"))))
      if (c.spec->method == Method::Classical && c.spec->integrator == Integrator::RK4) {
        ++untuned;
        CHECK((c.tuning.empty() && c.name == "iftomm_a04.classical.rk4.0.001"));
      }
    CHECK(untuned == 1);
  }
  {  // a closure's option on a tree: the tuned runs would be the untuned ones again; left out and said
    json tree = plan;
    tree["scenes"] = {test::sourcePath("data/scenes/pendulum5.json")};
    tree["lines"] = {plan["lines"][0], plan["lines"][1]};
    const Plan t = loadPlan(writePlan(tree, "tree.json"));
    std::vector<std::string> runs;
    for (const SweepCase& c : planCases(t))
      if (c.role == CaseRole::Run) runs.push_back(c.name);
    CHECK(runs == std::vector<std::string>{"pendulum5.mujoco.rk4.0.001"});
    CHECK_THAT(leftOutLines(t), Catch::Contains("**Not run on pendulum5**: 2 cases of tuning sets that set closures' options"));
  }
  const Plan p = loadPlan(writePlan(plan, "tuned.json"));
  std::vector<std::string> names;
  for (const SweepCase& c : planCases(p))
    if (c.role == CaseRole::Run) names.push_back(c.name);
  const std::vector<std::string> expected = {
      "iftomm_a04.mujoco.rk4.0.001", "iftomm_a04.mujoco.rk4.0.001.mujoco_solref_time-0.005",
      "iftomm_a04.mujoco.rk4.0.001.mujoco_solref_damping-2.mujoco_solref_time-0.1",  // keys in name order
      "iftomm_a04.classical.augmented-lagrangian.trapezoidal.0.01.al_penalty_ratio-1e+06"};
  CHECK(names == expected);
  for (const SweepCase& c : planCases(p)) {
    if (c.name == expected[1]) CHECK(c.spec->options.params.at("mujoco_solref_time") == 0.005);
    if (c.name == expected[2]) CHECK((c.tuning == "mujoco_solref_damping=2 mujoco_solref_time=0.1" && c.spec->options.params.at("mujoco_solref_damping") == 2));
    if (c.name == expected[0]) CHECK(c.spec->options.params.count("mujoco_solref_time") == 0);
    if (c.name == expected[3]) CHECK(c.spec->options.loops.penalty_ratio == 1e6);
  }
  // Run: the sets reach the engine. MuJoCo's closures are soft: a time constant 20x shorter holds the loops tighter.
  const std::string dir = kDir + "/tuned";
  fs::remove_all(dir);
  REQUIRE(shell(eigenmass() + " sweep " + writePlan(plan, "tuned.json") + " --results " + dir + " -j 1 >/dev/null 2>&1") == 0);
  std::vector<std::string> missing;
  const std::vector<CaseRecord> rs = collectRecords(p, dir, missing);
  REQUIRE(missing.empty());
  std::map<std::string, const CaseRecord*> by;
  for (const CaseRecord& r : rs) by[r.name] = &r;
  REQUIRE((by[expected[0]]->loop_position_m && by[expected[1]]->loop_position_m));
  INFO("violation at solref 0.02 (default) " << *by[expected[0]]->loop_position_m << ", at 0.005 " << *by[expected[1]]->loop_position_m);
  CHECK(*by[expected[1]]->loop_position_m < 0.5 * *by[expected[0]]->loop_position_m);
  CHECK(by[expected[1]]->tuning == "mujoco_solref_time=0.005");
  CHECK(by[expected[0]]->tuning.empty());
  const std::string page = readFile(dir + "/tuned.md", "tables");
  CHECK_THAT(page, Catch::Contains("mujoco [mujoco_solref_time=0.005]"));
  CHECK(readFile(dir + "/tuned.csv", "merged").find(",mujoco_solref_damping=2 mujoco_solref_time=0.1,") != std::string::npos);

  // Refused in one line, naming the key: an option no method of the line reads, one set split over two
  // methods (each would run it untuned), the penalty without the augmented Lagrangian, a set twice, a value
  // out of its row's range, and a key set at the top level too.
  json bad = plan;
  bad["lines"][1]["tuning"] = {{{"ode_erp", 0.5}}};
  CHECK_THAT(planError(bad), Catch::Contains("lines[1].tuning[0].ode_erp: not an option of this line's methods (mujoco_solref_time"));
  bad["lines"][1]["methods"] = {"mujoco", "eigen"};
  bad["lines"][1]["tuning"] = {{{"refine", 1}, {"mujoco_solref_time", 0.005}}};
  CHECK_THAT(planError(bad), Catch::Contains("lines[1].tuning[0]: no method of this line reads all of its options"));
  bad = plan;
  bad["lines"][2]["formulations"] = {"projection"};
  bad["lines"][2]["integrator"] = "rk4";
  CHECK_THAT(planError(bad), Catch::Contains("lines[2].tuning[0].al_penalty_ratio: read by the formulation augmented-lagrangian only"));
  // The penalty's set beside a formulation the line's integrator cannot run: refused as without the set
  // (a hostile pass found the projection's case silently dropped).
  bad = plan;
  bad["lines"][2]["formulations"] = {"augmented-lagrangian", "projection"};
  CHECK_THAT(planError(bad), Catch::Contains("runs the formulation augmented-lagrangian, not projection"));
  bad = plan;
  bad["lines"][1]["tuning"][1] = {{"mujoco_solref_time", 0.005}};
  CHECK_THAT(planError(bad), Catch::Contains("lines[1].tuning[1]: the same set twice"));
  bad = plan;
  bad["lines"][1]["tuning"][0]["mujoco_solref_time"] = 5000;
  CHECK_THAT(planError(bad), Catch::Contains("lines[1].tuning[0].mujoco_solref_time: must be in (0, 1000], got 5000"));
  bad = plan;
  bad["lines"][1]["tuning"] = json::array();
  CHECK_THAT(planError(bad), Catch::Contains("lines[1].tuning:"));
  bad = plan;
  bad["lines"][1]["tuning"][0] = json::object();
  CHECK_THAT(planError(bad), Catch::Contains("lines[1].tuning[0]: expected an object of option values"));
  bad = plan;
  bad["mujoco_solref_time"] = 0.01;
  CHECK_THAT(planError(bad), Catch::Contains("lines[1].tuning[0].mujoco_solref_time: also set at the plan's top level"));

  // A hostile pass (this session): values past gnum's six digits named two runs alike, so a changed value
  // reused the old one's result; refine_tol without refine was run as the default; sets were unbounded;
  // an ensemble pooled tuned and untuned routes; a solref below two steps failed only once running.
  bad = plan;
  bad["lines"][1]["tuning"] = {{{"mujoco_solref_time", 0.1234574}}, {{"mujoco_solref_time", 0.123457}}};
  {
    std::set<std::string> names;
    for (const SweepCase& c : planCases(loadPlan(writePlan(bad, "exact.json")))) names.insert(c.name);
    CHECK(names.count("iftomm_a04.mujoco.rk4.0.001.mujoco_solref_time-0.1234574") == 1);
    CHECK(names.count("iftomm_a04.mujoco.rk4.0.001.mujoco_solref_time-0.123457") == 1);
  }
  bad = plan;
  bad["lines"][1]["methods"] = {"eigen-jacobi"};
  bad["lines"][1]["tuning"] = {{{"refine_tol", 1e-9}}};
  CHECK_THAT(planError(bad), Catch::Contains("lines[1].tuning[0].refine_tol: read only with refine > 0, and refine is 0"));
  bad["lines"][1]["tuning"] = {{{"refine_tol", 1e-9}, {"refine", 2}}};
  CHECK(planError(bad).empty());
  bad = plan;
  bad["lines"][1]["tuning"] = json::array();
  for (int k = 0; k < 101; ++k) bad["lines"][1]["tuning"].push_back({{"mujoco_solref_time", 0.005 + 1e-4 * k}});
  CHECK_THAT(planError(bad), Catch::Contains("lines[1].tuning: 101 sets, more than 100"));
  bad = plan;
  bad["ensemble"] = {{"count", 2}, {"seed", 1}, {"perturb", {{"q", 1e-3}}}};
  bad["repeats"] = 1;
  CHECK_THAT(planError(bad), Catch::Contains("lines[1].tuning: not with an ensemble"));
  bad = plan;
  bad["lines"][1]["tuning"] = {{{"mujoco_solref_time", 0.001}}};  // dt 1e-3: MuJoCo would raise it to 2 dt
  CHECK_THAT(planError(bad), Catch::Contains("lines: iftomm_a04.mujoco.rk4.0.001.mujoco_solref_time-0.001: mujoco_solref_time 0.001: "
                                             "below two steps"));
}

TEST_CASE("a case file says how far its scene's start was assembled, as simulate's sidecar does", "[sweep][mechanism][cli]") {
  // Issue 73's doubtful list: a scene with simulate.assemble ran assembled, and its case files did not say so.
  nlohmann::json doc;
  std::ifstream(test::sourcePath("data/scenes/mechanisms/iftomm_a02_n2.json")) >> doc;
  doc["bodies"][1]["joint"]["q0"][0] = doc["bodies"][1]["joint"]["q0"][0].get<double>() + 0.01;  // open by ~0.01 m
  doc["simulate"]["assemble"] = true;
  fs::create_directories(kDir);
  std::ofstream(kDir + "/open_a02.json") << doc.dump();
  json plan = smallPlan();
  plan["name"] = "assembled";
  plan["scenes"] = {kDir + "/open_a02.json"};
  plan["t_end"] = 0.1;
  plan["output_dt"] = 0.05;
  plan["lines"] = {{{"methods", {"classical"}}, {"integrator", "rk4"}, {"dt", {1e-2}}}};
  plan["tables"] = {"runs"};
  const std::string dir = kDir + "/assembled";
  fs::remove_all(dir);
  REQUIRE(shell(eigenmass() + " sweep " + writePlan(plan, "assembled.json") + " --results " + dir + " -j 1 >/dev/null 2>&1") == 0);
  for (const char* file : {"/open_a02.reference.json", "/open_a02.classical.rk4.0.01.json"}) {
    const json c = readJsonFile(dir + file, "case");
    INFO(file);
    CHECK(c.at("scene_source").at("assembly").at("gap_before").get<double>() > 5e-3);
    CHECK(c.at("scene_source").at("sha256") == c.at("key").at("scene_sha256"));
  }
}
