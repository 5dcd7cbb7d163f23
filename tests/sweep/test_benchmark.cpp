// The benchmark (compare/benchmark.cpp, sweep/benchmark_tables.cpp,
// app/cmd_benchmark.cpp): a problem's error measure against closed forms,
// each route's cheapest run within a level and why one never got there, the
// plan's formulations, and the command end to end on two shipped problems
// and one it has never seen.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "app/cli_support.hpp"
#include "compare/benchmark.hpp"
#include "compare/engines.hpp"
#include "reference/engine.hpp"
#include "io/json_input.hpp"
#include "io/scene.hpp"
#include "solver/rotation.hpp"
#include "sweep/sweep.hpp"

using namespace em;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

// A measure of one point of body "b" at (0.5, 0, 0), its x, over `outputs` steps of t_end.
BenchmarkSpec spec(double t_end, int outputs, std::vector<double> levels = {1e-1, 1e-3}) {
  BenchmarkSpec s;
  s.problem = "T";
  s.measure = {{"tip_x", "b", Vec3(0.5, 0, 0), 0}};
  s.t_end = t_end, s.outputs = outputs, s.levels = levels;
  return s;
}

// A body "b" turning about z at `rate` (rad/s) about its CM at the origin, sampled every `dt` up to t_end.
Trajectory turning(double rate, double dt, double t_end) {
  Trajectory tr;
  tr.body_names = {"a", "b"};
  tr.run.t_end = t_end;
  for (long k = 0; k * dt <= t_end * (1 + 1e-12); ++k) {
    const double t = k * dt;
    tr.t.push_back(t);
    Pose still, b;
    b.quat = matrixToQuat(rot(Vec3::UnitZ(), rate * t));
    tr.poses.push_back({still, b});
  }
  return tr;
}


CaseRecord run(const std::string& method, const std::string& formulation, const std::string& integrator, double dt,
               std::optional<double> err, double cpu, Outcome status = Outcome::Ok) {
  CaseRecord r;
  r.role = CaseRole::Run, r.scene = "s", r.method = method, r.formulation = formulation, r.integrator = integrator;
  r.setting_kind = SettingKind::Dt, r.setting = dt, r.status = status;
  if (status != Outcome::Ok) r.failure_kind = Failure::LoopsOpen, r.failure_time = 0.5;
  r.has_error = true, r.benchmark_error = err, r.cpu_s = {cpu, cpu, cpu};
  r.loop_position_m = 1e-9;
  r.name = method + "." + formulation + "." + integrator + "." + std::to_string(dt);
  return r;
}

}  // namespace

TEST_CASE("the benchmark error is the largest gap of the measured coordinate over the output steps", "[benchmark]") {
  // Two tips turning at 1 and 1.1 rad/s: x = 0.5 cos(w t), the gap 0.5 |cos t - cos 1.1 t|, in closed form.
  const Trajectory ref = turning(1.0, 0.01, 2.0), run = turning(1.1, 0.01, 2.0);
  const BenchmarkError e = benchmarkError(spec(2.0, 20), run, ref);
  double expect = 0, at = 0;
  for (int k = 1; k <= 20; ++k) {
    const double t = 0.1 * k, d = 0.5 * std::abs(std::cos(t) - std::cos(1.1 * t));
    if (d > expect) expect = d, at = t;
  }
  CHECK(e.steps == 20);
  CHECK(e.max_abs == Approx(expect).epsilon(1e-12));  // the same cosines, through quaternions: round-off only
  CHECK(e.at_t == Approx(at));
  CHECK(e.at == "tip_x");
  // Only the output steps count: samples between them (every 0.01 s) are not the measure.
  const BenchmarkError coarse = benchmarkError(spec(2.0, 2), run, ref);
  CHECK(coarse.steps == 2);
  CHECK(coarse.max_abs == Approx(0.5 * std::abs(std::cos(2.0) - std::cos(2.2))).epsilon(1e-12));
  // A shorter horizon measures the steps within it.
  const Trajectory short_run = turning(1.1, 0.01, 0.5), short_ref = turning(1.0, 0.01, 0.5);
  CHECK(benchmarkError(spec(2.0, 20), short_run, short_ref).steps == 5);
  // A grid that does not hold the steps is refused, naming the step.
  CHECK_THROWS_WITH(benchmarkError(spec(2.0, 30), run, ref), Catch::Contains("is not a sample of the run"));
  // A failed run is measured up to its failure.
  Trajectory failed = turning(1.1, 0.01, 2.0);
  failed.t.resize(101), failed.poses.resize(101);  // up to t = 1
  markFailed(failed, 1.005, Failure::BlowUp, "test");
  CHECK(benchmarkError(spec(2.0, 20), failed, ref).steps == 10);
  markFailed(failed, 1.0, Failure::BlowUp, "test");  // failed at an output step's time, its sample not written
  failed.t.resize(100), failed.poses.resize(100);
  CHECK(benchmarkError(spec(2.0, 20), failed, ref).steps == 9);
}

TEST_CASE("the benchmark key of a scene is checked and written back", "[benchmark][io]") {
  const std::string path = test::sourcePath("data/scenes/mechanisms/iftomm_a02_n2.json");
  const std::string text = readFile(path, "scene");
  const SceneSpec s = parseSceneSpec(text);
  REQUIRE(s.benchmark);
  CHECK(s.benchmark->problem == "A02-N2");
  CHECK(s.benchmark->outputStep() == Approx(0.05));
  CHECK(parseSceneSpec(sceneJson(s)).benchmark->levels == s.benchmark->levels);  // round trip
  const auto refused = [&](const std::string& from, const std::string& to, const std::string& says) {
    std::string bad = text;
    const size_t at = bad.find(from);
    REQUIRE(at != std::string::npos);
    bad.replace(at, from.size(), to);
    INFO(to);
    CHECK_THROWS_WITH(parseSceneSpec(bad), Catch::Contains(says));
  };
  refused("\"body\": \"crank0\"", "\"body\": \"crank9\"", "benchmark.measure[0].body: no body named 'crank9'");
  refused("\"axis\": \"x\"", "\"axis\": \"w\"", "benchmark.measure[0].axis: 'w' is not a world axis");
  refused("\"levels\": [0.1, 0.001]", "\"levels\": [0.001, 0.1]", "benchmark.levels[1]: levels go from coarse to fine");
  refused("\"outputs\": 400", "\"outputs\": 400.5", "benchmark.outputs");
  refused("\"outputs\": 400", "\"outputs\": 0", "benchmark.outputs");
  refused("\"outputs\": 400", "\"outputs\": 400, \"extra\": 1", "benchmark.extra: unknown key");
  // The problem's solution: a row per output step, each the measured coordinates; written back as read.
  REQUIRE(s.benchmark->solution.size() == 400);
  CHECK(parseSceneSpec(sceneJson(s)).benchmark->solution == s.benchmark->solution);
  refused("\"solution\": [\n   [0.05021761829020563],", "\"solution\": [\n", "benchmark.solution: expected a row per output step: 400 rows, got 399");
  refused("[0.05021761829020563]", "[0.05, 0.1]", "benchmark.solution[0]: expected 1 number, got 2");
  refused("[0.05021761829020563]", "[\"0.05\"]", "benchmark.solution[0][0]: expected a number");
  refused("[0.05021761829020563]", "[1e5]", "benchmark.solution[0][0]: 100000 m beyond +-10000 m");
  refused("\"solution\": [", "\"solution\": 3, \"x-rows\": [", "benchmark.solution: expected a row per output step: 400 rows, got number");
}

namespace {

// `scene` (data/scenes/mechanisms/) run by classical rk8pd at `tol` (the projection on a mechanism) to t_end,
// sampled every `output_dt`, measured against its benchmark's solution.
BenchmarkError againstSolution(const std::string& scene, double tol, double t_end, double output_dt) {
  const Scene sc = loadScene(test::sourcePath("data/scenes/mechanisms/" + scene));
  RunSpec rs;
  rs.method = Method::Classical, rs.integrator = Integrator::RK8PD, rs.tol = tol, rs.t_end = t_end, rs.output_dt = output_dt;
  const Trajectory tr = runTrajectory(sc.model, checked(rs));
  REQUIRE_FALSE(tr.failed());
  return solutionError(*sc.benchmark, tr);
}

}  // namespace

TEST_CASE("A01's and A02's shipped solutions are the scenes' own motion", "[benchmark][mechanism]") {
  // The solutions come from outside the solver (tools/make_mechanisms.py: Jacobi's elliptic functions for A01,
  // SciPy's DOP853 on A02's one-degree-of-freedom equation of the parallel branch), good to ~1e-10 m. rk8pd
  // at 1e-12 on the scenes' own equations agrees to its tolerance over the steps below: a wrong inertia, sign or
  // measured point in either would show at 1e-3 or more.
  const BenchmarkError a01 = againstSolution("iftomm_a01.json", 1e-12, 20, 0.5);  // 40 steps of the 4000
  CHECK(a01.steps == 40);
  CHECK(a01.max_abs < 1e-9);
  // A02 (N = 2) up to 0.7 s, before its first singular position (0.714 s), where the scene's runs lose accuracy.
  const BenchmarkError a02 = againstSolution("iftomm_a02_n2.json", 1e-12, 0.7, 0.05);
  CHECK(a02.steps == 14);
  CHECK(a02.max_abs < 1e-9);
  const BenchmarkError a02_40 = againstSolution("iftomm_a02_n40.json", 1e-12, 0.5, 0.05);
  CHECK(a02_40.steps == 10);
  CHECK(a02_40.max_abs < 1e-9);
}

TEST_CASE("the benchmark table: each route's cheapest run within a level, why others never got there, and the goal", "[benchmark][sweep]") {
  useEngines();
  const std::vector<CaseRecord> rs = {
      run("classical", "projection", "rk4", 1e-2, 5e-2, 0.01), run("classical", "projection", "rk4", 1e-3, 5e-4, 0.1),
      run("classical", "udwadia-kalaba", "rk4", 1e-3, 2e-2, 0.05),
      run("classical", "", "ida", 1e-6, 1e-4, 0.2),
      run("mujoco", "", "rk4", 1e-3, 8e-2, 0.02), run("mujoco", "", "rk4", 1e-4, 5e-3, 0.2),
      run("dart", "", "dart-euler", 1e-3, std::nullopt, 0.01, Outcome::Failed)};
  BenchmarkSpec b = spec(1.0, 10);
  const std::string md = benchmarkScene(rs, "s", b, 1.0);
  CHECK(lineOf(md, "| eigenmass | classical projection rk4 |") ==
        "| eigenmass | classical projection rk4 | 2 / 2 | dt 0.01 | 1.00e-02 | 1.00e-02 | 1.00e-09 | 0.00e+00 | dt 0.001 | 1.00e-01 | 1.00e-01 | 1.00e-09 | 0.00e+00 |");
  CHECK(lineOf(md, "| eigenmass | classical udwadia-kalaba rk4 |").find("not reached: best 2.00e-02 m (dt 0.001)") != std::string::npos);
  CHECK(lineOf(md, "| dart |").find("not reached: every run failed (finest: loops-open at 0.5 s)") != std::string::npos);
  CHECK(lineOf(md, "| ida | classical ida |").find("1e-06") != std::string::npos);  // IDA is its own owner
  CHECK(lineOf(md, "- Within 0.1 m") ==
        "- Within 0.1 m: eigenmass's fastest route is classical projection rk4 dt 0.01, 1.00e-02 CPU s; cheaper than every "
        "other owner's fastest (ida 20x, mujoco 2x): goal met.");
  CHECK(lineOf(md, "- Within 0.001 m") ==
        "- Within 0.001 m: eigenmass's fastest route is classical projection rk4 dt 0.001, 1.00e-01 CPU s; cheaper than every "
        "other owner's fastest (ida 2x): goal met.");
  const std::string summary = benchmarkSummary({{"s", b, rs, true}});
  CHECK(lineOf(summary, "| T | 0.1 |") == "| T | 0.1 | 1.00e-02 | 2.00e-01 | 2.00e-02 | - | classical projection rk4 dt 0.01 | met (no interval: not timed interleaved): next mujoco 2x dearer |");
  // An engine cheaper than eigenmass: the goal is missed, by how much.
  std::vector<CaseRecord> beaten = rs;
  beaten.push_back(run("ode", "", "ode-step", 1e-3, 1e-2, 0.004));
  CHECK(lineOf(benchmarkSummary({{"s", b, beaten, true}}), "| T | 0.1 |").find("missed (no interval: not timed interleaved): next ode 2.5x cheaper") != std::string::npos);
  CHECK(lineOf(benchmarkSummary({{"s", b, beaten, false}}), "| T | 0.1 |").find("not judged (incomplete)") != std::string::npos);
  // A check that failed before the horizon, or lies within ten times a level, leaves the level unjudged.
  std::vector<CaseRecord> checked = rs;
  CaseRecord chk = run("simbody", "", "rkmerson", 1e-12, 5e-4, 1.0, Outcome::Failed);
  chk.role = CaseRole::Check;
  checked.push_back(chk);
  CHECK(lineOf(benchmarkSummary({{"s", b, checked, true}}), "| T | 0.1 |").find("not judged: the reference's check failed at 0.5 s") != std::string::npos);
  CHECK(lineOf(benchmarkScene(checked, "s", b, 1.0), "- Within 0.1 m") == "- Within 0.1 m: not judged: the reference's check failed at 0.5 s.");
  checked.back().status = Outcome::Ok;
  CHECK(lineOf(benchmarkSummary({{"s", b, checked, true}}), "| T | 0.1 |").find("met") != std::string::npos);
  CHECK(lineOf(benchmarkSummary({{"s", b, checked, true}}), "| T | 0.001 |").find("not judged: the reference's check is 5.00e-04 m from it") != std::string::npos);
  // A problem with its own solution is judged against it: the reference's check no longer decides.
  checked.back().status = Outcome::Failed;
  BenchmarkSpec solved = b;
  solved.solution.assign(10, 0.0);
  CHECK(lineOf(benchmarkSummary({{"s", solved, checked, true}}), "| T | 0.1 |").find("next mujoco 2x dearer") != std::string::npos);
  const std::string md_solved = benchmarkScene(checked, "s", solved, 1.0);
  CHECK(md_solved.find("against the problem's solution (the scene's benchmark.solution)") != std::string::npos);
  CHECK(md_solved.find("The reference's check is 5.00e-04 m from the solution up to 0.5 s, where it failed (loops-open).") != std::string::npos);
}

TEST_CASE("a route whose error leaves a level as its setting tightens is not ranked there, marked not converging with both runs", "[benchmark][sweep]") {
  // Issue 76, item 5: A02's projection under rk8pd won both levels with 4.6e-6 m at tol 1e-4 while its
  // tol 1e-6 run was 3.7e-3 m off (docs/results.md). The rule: a run counts within a level only when every
  // finer run of its route completed within it too.
  useEngines();
  std::vector<CaseRecord> rs = {run("classical", "projection", "rk8pd", 1e-4, 4.6e-6, 0.1), run("classical", "projection", "rk8pd", 1e-6, 3.7e-3, 0.3),
                                run("classical", "augmented-lagrangian", "trapezoidal", 1e-2, 1.2e-3, 0.5),
                                run("classical", "augmented-lagrangian", "trapezoidal", 5e-3, 2.7e-4, 0.9),
                                run("ode", "", "ode-step", 1e-3, 9e-2, 96)};
  for (CaseRecord& r : rs)
    if (r.integrator == "rk8pd") r.setting_kind = SettingKind::Tolerance;
  const BenchmarkSpec b = spec(1.0, 10);
  const std::string md = benchmarkScene(rs, "s", b, 1.0);
  // Within 0.1 m both rk8pd runs are within: it counts there. Within 1e-3 m its finer run left the level.
  CHECK(lineOf(md, "| eigenmass | classical projection rk8pd |") ==
        "| eigenmass | classical projection rk8pd | 2 / 2 | tol 0.0001 | 1.00e-01 | 1.00e-01 | 1.00e-09 | 0.00e+00 | not converging: "
        "4.60e-06 m at tol 0.0001, 3.70e-03 m at tol 1e-06 | - | - | - | - |");
  CHECK(lineOf(md, "- Within 0.001 m").find("eigenmass's fastest route is classical augmented-lagrangian trapezoidal dt 0.005") != std::string::npos);
  // A finer run that failed breaks the convergence as well, named by how it ended.
  rs[1].status = Outcome::Failed, rs[1].failure_kind = Failure::LoopsOpen, rs[1].failure_time = 0.75;
  CHECK(lineOf(benchmarkScene(rs, "s", b, 1.0), "| eigenmass | classical projection rk8pd |").find(
            "not converging: 4.60e-06 m at tol 0.0001, loops-open at 0.75 s at tol 1e-06") != std::string::npos);
}

TEST_CASE("a plan line's formulations name its cases on a mechanism and fold away on a tree", "[benchmark][sweep]") {
  const std::string dir = std::string(EM_BINARY_DIR) + "/benchmark-plan-tests";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const auto plan = [&](const json& line, const json& tables = json::array()) {
    const std::string path = dir + "/p.json";
    std::ofstream(path) << json{{"format", "eigenmass-plan/1"}, {"name", "p"},
                                {"scenes", {test::sourcePath("data/scenes/mechanisms/iftomm_a02_n2.json"),
                                            test::sourcePath("data/scenes/mechanisms/iftomm_a01.json")}},
                                {"t_end", 1}, {"output_dt", 0.05},
                                {"reference", {{"method", "classical"}, {"integrator", "ida"}, {"tolerance", 1e-10}}},
                                {"lines", {line}}, {"tables", tables}}.dump();
    return path;
  };
  const Plan p = loadPlan(plan({{"methods", {"classical"}}, {"formulations", {"projection", "udwadia-kalaba"}}, {"integrator", "rk4"}, {"dt", {1e-3}}}));
  std::vector<std::string> names;
  for (const SweepCase& c : planCases(p)) names.push_back(c.name);
  CHECK(names == std::vector<std::string>{"iftomm_a02_n2.reference", "iftomm_a01.reference", "iftomm_a02_n2.classical.projection.rk4.0.001",
                                          "iftomm_a02_n2.classical.udwadia-kalaba.rk4.0.001", "iftomm_a01.classical.rk4.0.001"});
  CHECK(planCases(p)[3].spec->options.loops.formulation == Formulation::UdwadiaKalaba);
  CHECK_THROWS_WITH(loadPlan(plan({{"methods", {"classical"}}, {"formulations", {"lagrange"}}, {"integrator", "rk4"}, {"dt", {1e-3}}})),
                    Catch::Contains("lines[0].formulations[0]: unknown formulation 'lagrange'"));
  CHECK_THROWS_WITH(loadPlan(plan({{"methods", {"mujoco"}}, {"formulations", {"projection"}}, {"integrator", "rk4"}, {"dt", {1e-3}}})),
                    Catch::Contains("lines[0].methods[0]: mujoco closes loops its own way"));
  // Issue 73, item 9: runs that cannot run on their scene are refused when the plan loads, naming the case,
  // not loaded, listed and failed one by one (exit 1).
  CHECK_THROWS_WITH(loadPlan(plan({{"methods", {"classical"}}, {"formulations", {"augmented-lagrangian"}}, {"integrator", "rk4"}, {"dt", {1e-3}}})),
                    Catch::Contains("lines: iftomm_a02_n2.classical.augmented-lagrangian.rk4.0.001: formulation augmented-lagrangian runs "
                                    "under its own integrator trapezoidal"));
  CHECK_THROWS_WITH(loadPlan(plan({{"methods", {"classical"}}, {"formulations", {"projection"}}, {"integrator", "cvode"}, {"tolerance", {1e-6}}})),
                    Catch::Contains("lines: iftomm_a02_n2.classical.projection.cvode.1e-06: integrator cvode is multistep"));
  CHECK_THROWS_WITH(loadPlan(plan({{"methods", {"eigen"}}, {"integrator", "ida"}, {"tolerance", {1e-6}}})),
                    Catch::Contains("lines: iftomm_a02_n2.eigen.ida.1e-06: integrator ida integrates the formation's A and B itself"));
  // Issue 73, item 4: IDA under two formulations wrote two case files of one identical run.
  CHECK_THROWS_WITH(loadPlan(plan({{"methods", {"classical"}}, {"formulations", {"projection", "udwadia-kalaba"}}, {"integrator", "ida"},
                                   {"tolerance", {1e-6}}})),
                    Catch::Contains("lines[0].formulations: integrator ida closes the loops itself"));
  // ... and a work-precision row pooled three formulations under one method: each is its own row now.
  {
    const Plan wp = loadPlan(plan({{"methods", {"classical"}}, {"formulations", {"projection", "udwadia-kalaba"}}, {"integrator", "rk4"},
                                   {"dt", {1e-3, 5e-4}}},
                                  {"work-precision", "runs"}));
    std::vector<CaseRecord> rs = {run("classical", "projection", "rk4", 1e-3, 1e-3, 0.1), run("classical", "projection", "rk4", 5e-4, 1e-4, 0.2),
                                  run("classical", "udwadia-kalaba", "rk4", 1e-3, 5e-2, 0.1),
                                  run("classical", "udwadia-kalaba", "rk4", 5e-4, 4e-2, 0.2)};
    for (CaseRecord& r : rs) r.max_pose = *r.benchmark_error;
    const std::string md = sweepTables(wp, rs);
    CHECK(lineOf(md, "| classical projection | rk4 | 2 / 2 |").find("1.00e-04") != std::string::npos);
    CHECK(lineOf(md, "| classical udwadia-kalaba | rk4 | 2 / 2 |").find("4.00e-02") != std::string::npos);
    CHECK(lineOf(md, "| s | classical udwadia-kalaba | rk4 | 0.0005 |") != "");
  }
  // The benchmark table needs the scenes' benchmark steps on the plan's grid: A01 measures every 1 s, 0.05 divides it.
  CHECK_NOTHROW(loadPlan(plan({{"methods", {"classical"}}, {"integrator", "rk4"}, {"dt", {1e-3}}}, {"benchmark"})));
  const std::string bad = plan({{"methods", {"classical"}}, {"integrator", "rk4"}, {"dt", {1e-3}}}, {"benchmark"});
  json doc = json::parse(std::ifstream(bad));
  doc["output_dt"] = 0.03;
  std::ofstream(bad) << doc.dump();
  CHECK_THROWS_WITH(loadPlan(bad), Catch::Contains("output_dt: 0.03 s does not divide scene iftomm_a02_n2's benchmark output step 0.05 s"));
  doc["output_dt"] = 0.05;
  doc["scenes"] = {test::sourcePath("data/scenes/pendulum5.json")};
  std::ofstream(bad) << doc.dump();
  CHECK_THROWS_WITH(loadPlan(bad), Catch::Contains("benchmark: scene pendulum5 has no \"benchmark\" key"));
}

TEST_CASE("eigenmass benchmark runs two shipped problems and one never seen, every engine and formulation, resumably", "[benchmark][cli]") {
  const std::string dir = std::string(EM_BINARY_DIR) + "/benchmark-tests";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string tmpl = dir + "/template.json";
  std::ofstream(tmpl) << json{
      {"format", "eigenmass-plan/1"}, {"name", "template"}, {"scenes", json::array()}, {"t_end", 1}, {"repeats", 3},
      {"reference", {{"method", "classical"}, {"integrator", "rk8pd"}, {"tolerance", 1e-11}}},
      {"reference_check", {{"method", "simbody"}, {"integrator", "rkmerson"}, {"tolerance", 1e-12}}},
      {"lines", {{{"methods", {"classical", "articulated"}}, {"formulations", {"projection", "coordinate-partitioning"}}, {"integrator", "rk4"}, {"dt", {1e-2, 1e-3}}},
                 {{"methods", {"classical"}}, {"formulations", {"augmented-lagrangian"}}, {"integrator", "trapezoidal"}, {"dt", {1e-3}}},
                 {{"methods", {"classical"}}, {"integrator", "ida"}, {"tolerance", {1e-6}}},
                 {{"methods", {"mujoco"}}, {"integrator", "rk4"}, {"dt", {1e-3}}},
                 {{"methods", {"dart"}}, {"integrator", "dart-euler"}, {"dt", {1e-3}}},
                 {{"methods", {"bullet"}}, {"integrator", "bullet-euler"}, {"dt", {1e-3}}},
                 {{"methods", {"ode"}}, {"integrator", "ode-step"}, {"dt", {1e-3}}},
                 {{"methods", {"simbody"}}, {"integrator", "rkmerson"}, {"tolerance", {1e-6}}}}},
      {"tables", {"benchmark"}}}.dump(1);
  // A problem never seen: the slider-crank with a measure of the slider's x, given here.
  json crank = json::parse(std::ifstream(test::sourcePath("tests/scenes/mechanisms/slider_crank.json")));
  crank["benchmark"] = {{"problem", "crank"}, {"measure", {{{"name", "slider_x"}, {"body", "slider"}, {"axis", "x"}}}},
                        {"t_end", 2}, {"outputs", 20}, {"levels", {1e-2, 1e-5}}};
  const std::string unseen = dir + "/crank_problem.json";
  std::ofstream(unseen) << crank.dump(1);
  const std::string results = dir + "/results";
  const std::string args = "benchmark A01 A02-N2 " + unseen + " --plan " + tmpl + " --t-end 2 --results " + results;
  const Run r = eigenmass(args + " -j 2", true);
  INFO(r.out);
  REQUIRE(r.status == 0);
  const std::string summary = readFile(results + "/benchmark.md", "summary");
  for (const char* row : {"| A01 | 0.1 |", "| A01 | 0.001 |", "| A02-N2 | 0.1 |", "| A02-N2 | 0.001 |", "| crank | 0.01 |", "| crank | 1e-05 |"})
    CHECK(summary.find(row) != std::string::npos);
  for (const char* owner : {"| eigenmass |", "| ida |", "| mujoco |", "| dart |", "| bullet |", "| ode |", "| simbody |"})
    CHECK(summary.find(owner) != std::string::npos);
  const auto result = [&](const std::string& problem, const std::string& name) {
    return json::parse(std::ifstream(results + "/" + problem + "/" + name + ".json")).at("result");
  };
  // The check (Simbody at 1e-12) and the reference (rk8pd at 1e-11, projected) agree on B0's x within a tenth of
  // the finer level (1e-3 m), so it is resolved: each pass through a singular position (0.714 and 1.228 s) costs
  // both some accuracy (measured 1.3e-5 m over 2 s; docs/theory.md §15); on the tree A01 they agree to 1e-10.
  CHECK(result("iftomm_a02_n2", "iftomm_a02_n2.check").at("benchmark_error_m").get<double>() < 1e-4);
  CHECK(result("iftomm_a01", "iftomm_a01.check").at("benchmark_error_m").get<double>() < 1e-10);
  // rk4 with the loops projected: from dt 1e-2 to 1e-3 the error falls by at least 1e2 (fourth order: ~1e4),
  // and at 1e-3 it is within the finer level; coordinate partitioning the same to that level.
  const double coarse = result("iftomm_a02_n2", "iftomm_a02_n2.classical.projection.rk4.0.01").at("benchmark_error_m").get<double>();
  const double fine = result("iftomm_a02_n2", "iftomm_a02_n2.classical.projection.rk4.0.001").at("benchmark_error_m").get<double>();
  CHECK(fine < 1e-3);
  CHECK(coarse / fine > 1e2);
  CHECK(result("iftomm_a02_n2", "iftomm_a02_n2.articulated.coordinate-partitioning.rk4.0.001").at("benchmark_error_m").get<double>() < 1e-3);
  // Every mechanism run has its violation figure, the engines' too; a tree's formulations fold away.
  for (const char* name : {"iftomm_a02_n2.dart.dart-euler.0.001", "iftomm_a02_n2.bullet.bullet-euler.0.001", "iftomm_a02_n2.mujoco.rk4.0.001",
                           "iftomm_a02_n2.classical.augmented-lagrangian.trapezoidal.0.001"})
    CHECK(result("iftomm_a02_n2", name).at("loops_max_position_m").is_number());
  CHECK(fs::exists(results + "/iftomm_a01/iftomm_a01.classical.rk4.0.001.json"));
  CHECK(result("crank_problem", "crank_problem.ode.ode-step.0.001").at("benchmark_error_m").is_number());
  // Its figure: error against CPU time, a panel per owner.
  CHECK(eigenmass("plot " + results + "/iftomm_a02_n2 --out " + dir + "/figures").status == 0);
  CHECK(fs::exists(dir + "/figures/benchmark-iftomm_a02_n2.png"));
  // Resumes: the same command again runs nothing; --list prints one command per case of every problem.
  const std::string one = results + "/iftomm_a01/iftomm_a01.ode.ode-step.0.001.json";
  const auto written = fs::last_write_time(one);
  CHECK(eigenmass(args).status == 0);
  CHECK(fs::last_write_time(one) == written);
  const Run list = eigenmass(args + " --list");
  // Per problem: reference and check, rk4 2 methods x 2 dt (x 2 formulations on a mechanism), trapezoidal, ida, 5 engine runs.
  CHECK(std::count(list.out.begin(), list.out.end(), '\n') == (2 + 4 + 1 + 1 + 5) + 2 * (2 + 8 + 1 + 1 + 5));
  // Bad arguments are one line, exit 2, before any file.
  const Run unknown = eigenmass("benchmark A09 --results " + dir + "/none", true);
  CHECK(unknown.status == 2);
  CHECK(unknown.out.find("PROBLEM 'A09': neither a shipped problem (") != std::string::npos);
  const Run no_key = eigenmass("benchmark " + test::sourcePath("tests/scenes/mechanisms/slider_crank.json") + " --results " + dir + "/none", true);
  CHECK(no_key.status == 2);
  CHECK(no_key.out.find("slider_crank.json: benchmark: missing") != std::string::npos);
  const Run beyond = eigenmass("benchmark A02-N2 --t-end 30 --results " + dir + "/none", true);
  CHECK(beyond.status == 2);
  CHECK(beyond.out.find("--t-end: 30 s beyond problem A02-N2's horizon 20 s") != std::string::npos);
  CHECK_FALSE(fs::exists(dir + "/none"));
}

TEST_CASE("a summary margin is the median of interleaved rounds' ratios with its 10th-90th percentile: met, tied or missed",
          "[benchmark][sweep]") {
  // Issue 76, item 3: a margin has an interval. The verdict: met where every compared owner's interval lies
  // above 1, tied where one holds 1, missed where one lies below; the nearest owner is named with its interval.
  useEngines();
  const std::vector<CaseRecord> rs = {run("classical", "projection", "rk4", 1e-2, 5e-2, 0.01), run("mujoco", "", "rk4", 1e-3, 8e-2, 0.02),
                                      run("ode", "", "ode-step", 1e-3, 8e-2, 0.03), run("dart", "", "dart-euler", 1e-3, 8e-2, 0.5)};
  BenchmarkSpec b = spec(1.0, 10);
  b.levels = {0.1};
  // The contenders: eigenmass's fastest run and the two cheapest other owners' (not DART, 25x dearer).
  const std::vector<std::string> c = benchmarkContenders(rs, "s", b);
  REQUIRE(c.size() == 3);
  CHECK(c[0] == rs[0].name);
  CHECK(c[1] == rs[1].name);
  CHECK(c[2] == rs[2].name);
  // 11 rounds; per-round ratios mujoco / eigenmass: 1.5 .. 2.5 by 0.1 (median 2, 10th percentile 1.6, 90th 2.4).
  Interleaved t;
  t.rounds = 11;
  for (int k = 0; k < 11; ++k) {
    t.cpu_s[rs[0].name].push_back(0.01);
    t.cpu_s[rs[1].name].push_back(0.01 * (1.5 + 0.1 * k));
    t.cpu_s[rs[2].name].push_back(0.03);
  }
  const std::optional<Margin> m = interleavedMargin(t, rs[0].name, rs[1].name);
  REQUIRE(m);
  CHECK(m->median == Approx(2.0));
  CHECK(m->p10 == Approx(1.6));
  CHECK(m->p90 == Approx(2.4));
  BenchmarkProblem p{"s", b, rs, true, t};
  CHECK(lineOf(benchmarkSummary({p}), "| T | 0.1 |").find("| met: next mujoco 2x dearer [1.6, 2.4] |") != std::string::npos);
  // eigenmass's run is its route's only, so its finest: nothing finer shows it converges, and the summary says so.
  CHECK(lineOf(benchmarkSummary({p}), "| T | 0.1 |").find("classical projection rk4 dt 0.01 (its finest: convergence unchecked) |") != std::string::npos);
  // Rounds that straddle 1: tied, however the medians of the consecutive repeats ranked them.
  for (int k = 0; k < 11; ++k) p.interleaved.cpu_s[rs[1].name][k] = 0.01 * (0.7 + 0.06 * k);
  CHECK(lineOf(benchmarkSummary({p}), "| T | 0.1 |").find("| tied: mujoco 1x [0.76, 1.24] |") != std::string::npos);
  // Every round cheaper than eigenmass: missed, with the ratio's interval.
  for (int k = 0; k < 11; ++k) p.interleaved.cpu_s[rs[1].name][k] = 0.005;
  CHECK(lineOf(benchmarkSummary({p}), "| T | 0.1 |").find("| missed: mujoco 2x cheaper (ratio 0.5 [0.5, 0.5]) |") != std::string::npos);
  // The second owner decides as well: mujoco clearly dearer, ode tied.
  for (int k = 0; k < 11; ++k) {
    p.interleaved.cpu_s[rs[1].name][k] = 0.02;
    p.interleaved.cpu_s[rs[2].name][k] = 0.01 * (0.7 + 0.06 * k);
  }
  CHECK(lineOf(benchmarkSummary({p}), "| T | 0.1 |").find("| tied: ode 1x [0.76, 1.24] |") != std::string::npos);
  // An owner more than ten times dearer by the medians is not timed again: its margin comes from the repeats' extremes.
  std::vector<CaseRecord> far = {rs[0], rs[1], run("ode", "", "ode-step", 1e-3, 8e-2, 0.5)};
  far[2].cpu_s = {0.4, 0.5, 0.6};
  const std::vector<std::string> timed = benchmarkContenders(far, "s", b);
  CHECK(timed == std::vector<std::string>{rs[0].name, rs[1].name});
  Interleaved only;
  only.rounds = 11;
  only.cpu_s[rs[0].name] = t.cpu_s[rs[0].name];
  only.cpu_s[rs[1].name] = std::vector<double>(11, 0.02);
  BenchmarkProblem q{"s", b, far, true, only};
  CHECK(lineOf(benchmarkSummary({q}), "| T | 0.1 |").find("| met: next mujoco 2x dearer [2, 2] |") != std::string::npos);
  far.erase(far.begin() + 1);  // ODE alone: 50x by the medians, [40, 60] by its repeats' extremes over eigenmass's 0.01
  BenchmarkProblem r{"s", b, far, true, only};
  CHECK(lineOf(benchmarkSummary({r}), "| T | 0.1 |").find("| met: next ode 50x dearer [40, 60] |") != std::string::npos);
}
