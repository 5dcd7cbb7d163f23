// The CLI as a user runs it: exit codes, one-line errors, JSON and CSV outputs.
#include <catch2/catch.hpp>

#include <functional>
#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <set>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "app/cli_support.hpp"
#include "engines.hpp"
#include "support.hpp"


TEST_CASE("equations prints A B udot energy and eigenvalues and the simbody engine agrees", "[cli][crosscheck]") {
  const Run a = eigenmass("equations " + scene("pendulum5.json"));
  const Run b = eigenmass("equations " + scene("pendulum5.json") + " --engine simbody");
  REQUIRE(a.status == 0);
  REQUIRE(b.status == 0);
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  CHECK(ja["nq"] == 7);
  CHECK(ja["nu"] == 7);
  CHECK(ja["A"].size() == 7);
  CHECK(ja["A"][0].size() == 7);
  CHECK(ja["energy"]["total"].get<double>() == Approx(-96.927410600287).epsilon(1e-13));
  double amax = 0, diff = 0;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j) {
      amax = std::max(amax, std::abs(jb["A"][i][j].get<double>()));
      diff = std::max(diff, std::abs(ja["A"][i][j].get<double>() - jb["A"][i][j].get<double>()));
    }
  CHECK(diff <= 1e-12 * amax);
  for (int i = 0; i < 7; ++i)
    CHECK(ja["eigenvalues"][i].get<double>() == Approx(jb["eigenvalues"][i].get<double>()).epsilon(1e-12));
}

TEST_CASE("a malformed scene is one line on stderr and exit status 2", "[cli][scene]") {
  const std::string bad = em::test::sourcePath("tests/scenes/malformed/zero_axis.json");
  const Run r = eigenmass("equations " + bad, true);
  CHECK(r.status == 2);
  CHECK(r.out == "eigenmass: error: " + bad + ": bodies[1].joint.axis: zero axis\n");
}

TEST_CASE("a run over 2 s shows its progress on stderr when asked and only then", "[cli][progress]") {
  // 1000 s of pendulum5 at rk4 dt 1e-3 take ~6 s of CPU here: well past the 2 s
  // after which progress shows (400 s, 2.3 s since classical got faster, was too
  // close to it). stderr is a pipe here, not a terminal.
  const std::string out = std::string(EM_BINARY_DIR) + "/cli_progress.csv";
  const std::string run = "simulate " + scene("pendulum5.json") + " --t-end 1000 --out " + out;
  const Run asked = eigenmass(run + " --progress", true);
  CHECK(asked.status == 0);
  CHECK(asked.out.find("pendulum5 classical/rk4: t = ") != std::string::npos);
  CHECK(asked.out.find(" / 1000 s, elapsed ") != std::string::npos);
  CHECK(asked.out.find(", ETA ") != std::string::npos);
  const Run quiet = eigenmass(run, true);
  CHECK(quiet.status == 0);
  CHECK(quiet.out.find("ETA") == std::string::npos);
  CHECK(eigenmass(run + " --progress --no-progress", true).status == 2);
}

TEST_CASE("simulate writes the CSV it names and reports the energy drift", "[cli]") {
  const std::string out = std::string(EM_BINARY_DIR) + "/cli_sim/chain02.csv";
  std::filesystem::remove_all(std::string(EM_BINARY_DIR) + "/cli_sim");
  const Run r = eigenmass("simulate " + scene("chain02.json") + " --method eigen-jacobi --t-end 0.2 --out " + out);
  CHECK(r.status == 0);
  CHECK(r.out.find("status ok") != std::string::npos);
  CHECK(r.out.find("max |E(t) + W_diss(t) - E(0)|") != std::string::npos);
  std::ifstream in(out);
  std::string header;
  std::getline(in, header);
  CHECK(header.rfind("t,link1.q0,link1.q1,link1.q2,link2.q0,link1.u0", 0) == 0);
  int rows = 0;
  for (std::string line; std::getline(in, line);) ++rows;
  CHECK(rows == 21);
}

TEST_CASE("bad options are one-line errors - --help documents defaults", "[cli]") {
  const Run r = eigenmass("simulate " + scene("chain02.json") + " --dt 0.003 --t-end 1", true);
  CHECK(r.status == 2);
  CHECK(r.out.find("output_dt must be a whole multiple of dt") != std::string::npos);
  const Run h = eigenmass("simulate --help");
  CHECK(h.status == 0);
  CHECK(h.out.find("--dt") != std::string::npos);
  CHECK(h.out.find("0.001") != std::string::npos);
}

TEST_CASE("compare writes the report and prints the table - a broken gate exits 1", "[cli][comparison]") {
  const std::string dir = std::string(EM_BINARY_DIR) + "/cli_compare";
  std::filesystem::remove_all(dir);
  const std::string base = "compare " + scene("chain02.json") + " --t-end 0.3 --methods classical,eigen";
  const Run r = eigenmass(base + " --out " + dir + "/r.json --csv-dir " + dir + "/csv");
  CHECK(r.status == 0);
  CHECK(r.out.find("eigen ") != std::string::npos);
  std::ifstream in(dir + "/r.json");
  const auto j = nlohmann::json::parse(in);
  CHECK(j["format"] == "eigenmass-report/1");
  CHECK(j["methods"].size() == 2);
  CHECK(std::filesystem::exists(dir + "/csv/eigen.csv"));
  CHECK(std::filesystem::exists(dir + "/csv/reference.csv"));
  // A tolerance file with an impossible bound for this scene.
  const std::string tol = dir + "/tol.json";
  std::ofstream(tol) << R"({"format": "eigenmass-tolerances/1", "scenes": {"chain02": {"horizon_s": 0.3,
    "inhouse": {"integrator": "rk4", "dt": 0.001},
    "methods": {"classical": {"max_pose_error_rad": {"value": 1e-30, "reason": "impossible"}}}}}})";
  const Run g = eigenmass(base + " --out " + dir + "/g.json --gate " + tol);
  CHECK(g.status == 1);
  CHECK(g.out.find("gate broken: classical max_pose_error_rad") != std::string::npos);
  std::ifstream gin(dir + "/g.json");
  CHECK(nlohmann::json::parse(gin)["gate"]["passed"] == false);
}

TEST_CASE("compare reports the reference motion's Lyapunov exponent and says it under the table", "[cli][comparison][lyapunov]") {
  // pendulum5 is chaotic: 1.43 +- 0.32 /s over its 10 s (measured; docs/theory.md §11). Over
  // the 10 windows of 1 s the exponent stays positive beyond its own uncertainty.
  const std::string dir = std::string(EM_BINARY_DIR) + "/cli_lyapunov";
  std::filesystem::remove_all(dir);
  const Run r = eigenmass("compare " + scene("pendulum5.json") + " --methods classical --out " + dir + "/r.json");
  REQUIRE(r.status == 0);
  CHECK(r.out.find("finite-time Lyapunov exponent 1.43 /s over the 10 s of the run") != std::string::npos);
  CHECK(r.out.find("long-run exponent not measured") != std::string::npos);
  std::ifstream in(dir + "/r.json");
  const auto j = nlohmann::json::parse(in);
  const double chi = j["reference"]["lyapunov_per_s"], sigma = j["reference"]["lyapunov_uncertainty_per_s"];
  CHECK(chi > 3 * sigma);
  CHECK(chi == Approx(1.43).epsilon(0.05));  // deterministic: the same twin direction and steps every run
  CHECK(j["reference"]["lyapunov"]["windows_per_s"].size() == 10);
  CHECK(j["reference"]["lyapunov"]["completed"] == true);
  // The windows spread far more than the standard error (1.03 against 0.32 /s, measured): both are reported.
  CHECK(j["reference"]["lyapunov"]["windows_std_per_s"].get<double>() > 2 * sigma);
  CHECK(j["reference"]["lyapunov_long"].contains("not_measured"));
}

// Issue 54 item 2: a reference balanced on a knife-edge. The Allegro hand at
// rest on q = 0 (an unstable equilibrium) keeps its exact zeros in every
// exact-arithmetic engine, so a check against Simbody cannot see that a
// 1e-10 nudge parts by O(1) within the horizon. The sensitivity twin does.
TEST_CASE("compare's reference has a sensitivity twin that calls a knife-edge scene ill-conditioned", "[cli][comparison]") {
  const std::string dir = std::string(EM_BINARY_DIR) + "/cli_sensitivity";
  std::filesystem::remove_all(dir);
  // pendulum5 over 1 s: chaotic (1.6 /s) but a 1e-10 start stays within ~1e-9 (measured 7.4e-9 rad over 2 s).
  const Run calm = eigenmass("compare " + scene("pendulum5.json") + " --methods classical --t-end 1 --out " + dir + "/p.json");
  REQUIRE(calm.status == 0);
  CHECK_THAT(lineOf(calm.out, "sensitivity twin"), Catch::EndsWith("rad: every threshold is well-conditioned"));
  std::ifstream pin(dir + "/p.json");
  const auto p = nlohmann::json::parse(pin)["reference"]["sensitivity_twin"];
  CHECK(p["sigma"] == 1e-10);
  CHECK(p["max_pose_rad"].get<double>() < 1e-8);
  CHECK(p["max_pose_rad"].get<double>() > 1e-11);  // it did move: the twin is not the reference itself
  CHECK(p["ill_conditioned_at_rad"].empty());
  // The Allegro hand at q = 0 over 2 s: the twin parts by ~pi (measured 3.14 rad), beyond both thresholds.
  const Run knife = eigenmass("compare " + em::test::sourcePath("data/robots/allegro_right_hand.urdf") +
                              " --balance-inertia --methods classical --t-end 2 --out " + dir + "/a.json");
  REQUIRE(knife.status == 0);
  CHECK_THAT(lineOf(knife.out, "sensitivity twin"), Catch::Contains("ILL-CONDITIONED at 0.001 rad, 0.1 rad"));
  std::ifstream ain(dir + "/a.json");
  const auto a = nlohmann::json::parse(ain)["reference"]["sensitivity_twin"];
  CHECK(a["max_pose_rad"].get<double>() > 1);
  CHECK(a["ill_conditioned_at_rad"] == nlohmann::json({1e-3, 1e-1}));
}

TEST_CASE("compare --lyapunov-long measures the long-run exponent apart from the run's finite-time one", "[cli][comparison][lyapunov]") {
  // Issue 41: pendulum5's 1.43 /s is the 10-s run's. Measured with this option: 1.64 +- 0.19 /s over
  // 30 s, 1.64 +- 0.06 over 300 s (10-s blocks); the ensemble's members' 10-s median is 1.72 (docs/results.md).
  const std::string dir = std::string(EM_BINARY_DIR) + "/cli_lyapunov_long";
  std::filesystem::remove_all(dir);
  const Run r = eigenmass("compare " + scene("pendulum5.json") + " --methods classical --t-end 1 --lyapunov-long 30 --out " +
                          dir + "/r.json");
  REQUIRE(r.status == 0);
  CHECK(r.out.find("long-run Lyapunov exponent 1.64 +- 0.19 /s over 30 s") != std::string::npos);
  std::ifstream in(dir + "/r.json");
  const auto l = nlohmann::json::parse(in)["reference"]["lyapunov_long"];
  CHECK(l["t_s"] == 30.0);
  CHECK(l["window_s"] == 10.0);
  CHECK(l["windows_per_s"].size() == 3);
  CHECK(l["per_s"].get<double>() == Approx(1.64).epsilon(0.01));  // deterministic, as the finite-time one
  CHECK(eigenmass("compare " + scene("pendulum5.json") + " --lyapunov-long 0 --out " + dir + "/x.json", true).status == 2);
  // Over several starts (issue 54 item 6): the mean and spread of the scene's and its neighbours' exponents.
  const Run starts = eigenmass("compare " + scene("pendulum5.json") + " --methods classical --t-end 1 --lyapunov-long 20 " +
                               "--lyapunov-starts 3 --out " + dir + "/s.json");
  REQUIRE(starts.status == 0);
  CHECK(starts.out.find("long-run exponent over 3 starts (the scene's and 2 displaced by 0.001 in q0 and u0): mean ") != std::string::npos);
  std::ifstream in_s(dir + "/s.json");
  const auto ls = nlohmann::json::parse(in_s)["reference"]["lyapunov_long"];
  CHECK(ls["starts"]["n"] == 3);
  CHECK(ls["starts"]["each"].size() == 3);
  CHECK(ls["starts"]["each"][0]["per_s"] == ls["per_s"]);  // the first start is the scene's own
  double mean = 0;
  for (const auto& e : ls["starts"]["each"]) mean += e["per_s"].get<double>() / 3;
  CHECK(ls["starts"]["mean_per_s"].get<double>() == Approx(mean).epsilon(1e-12));
  // Refused in one line before any run: without --lyapunov-long, beyond 64, on a scene with loops.
  const Run alone = eigenmass("compare " + scene("pendulum5.json") + " --lyapunov-starts 3 --out " + dir + "/y.json", true);
  CHECK(alone.status == 2);
  CHECK(alone.out.find("--lyapunov-starts: needs --lyapunov-long") != std::string::npos);
  CHECK(eigenmass("compare " + scene("pendulum5.json") + " --lyapunov-long 10 --lyapunov-starts 65 --out " + dir + "/y.json", true).status == 2);
  const Run loops = eigenmass("compare " + scene("mechanisms/iftomm_a02_n2.json") + " --lyapunov-long 10 --lyapunov-starts 2 --out " + dir + "/y.json", true);
  CHECK(loops.status == 2);
  CHECK(loops.out.find("has loops, which displaced starts would open") != std::string::npos);
  CHECK_FALSE(std::filesystem::exists(dir + "/y.json"));
}

TEST_CASE("compare --refine records the corrections per eigenfactor method and says so under the table", "[cli][comparison][refine]") {
  const std::string dir = std::string(EM_BINARY_DIR) + "/cli_refine";
  std::filesystem::remove_all(dir);
  const Run r = eigenmass("compare " + scene("chain02.json") + " --t-end 0.3 --methods classical,eigen,eigen-block --refine 2 --out " +
                          dir + "/r.json");
  REQUIRE(r.status == 0);
  CHECK(r.out.find("eigenfactor methods: 2 residual correction(s) per evaluation (--refine)") != std::string::npos);
  std::ifstream in(dir + "/r.json");
  const auto j = nlohmann::json::parse(in);
  CHECK(j["methods"][0].contains("refine") == false);  // classical: nothing to correct
  CHECK(j["methods"][1]["refine"] == 2);
  CHECK(j["methods"][2]["refine"] == 2);
  CHECK(j["methods"][2]["block_gap"] == 3e-2);
}

TEST_CASE("an interrupted compare leaves no report and no temporary, and says so in one line", "[cli][comparison]") {
  const std::string out = std::string(EM_BINARY_DIR) + "/cli_interrupted.json";
  const std::string err = std::string(EM_BINARY_DIR) + "/cli_interrupted.err";
  std::filesystem::remove(out);
  // pendulum5 over 10 s takes several seconds; SIGINT after one.
  const std::string cmd = "timeout -s INT 1 " + std::string(EM_BINARY_DIR) + "/bin/eigenmass compare " +
                          scene("pendulum5.json") + " --no-progress --out " + out + " >/dev/null 2>" + err;
  const int st = std::system(cmd.c_str());
  CHECK(WEXITSTATUS(st) != 0);
  CHECK_FALSE(std::filesystem::exists(out));
  CHECK_FALSE(em::test::temporaryLeft(out));
  std::ifstream in(err);
  const std::string said((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(said == "eigenmass: interrupted (SIGINT); no output was left half-written\n");  // --no-progress: nothing else
}

// Issue 73, item 10: a sweep's (a benchmark's, an engine study's) workers were
// reparented to PID 1 and kept writing case files after their parent ended.
TEST_CASE("a sweep's workers do not outlive eigenmass, however it ends, and leave no temporary", "[cli][sweep]") {
  const std::string d = std::string(EM_BINARY_DIR) + "/cli_orphan_workers";
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  // Two cases of many seconds each (300 s of pendulum5 at rk4 dt 1e-4), two workers.
  std::ofstream(d + "/plan.json") << R"({"format": "eigenmass-plan/1", "name": "orphan", "scenes": [")" << scene("pendulum5.json")
                                  << R"("], "t_end": 300, "output_dt": 0.1, "repeats": 3, "lines": [{"methods": ["classical"], "integrator": "rk4", "dt": [0.0001, 0.00005]}]})";
  for (const char* sig : {"TERM", "INT", "KILL"}) {
    std::filesystem::remove_all(d + "/res");
    // Find the workers, signal the parent, then every worker must be gone (or a zombie
    // awaiting init) within 2 s.
    const std::string script =
        std::string(EM_BINARY_DIR) + "/bin/eigenmass sweep " + d + "/plan.json --results " + d + "/res -j 2 >/dev/null 2>&1 & P=$!; "
        "C=; for i in $(seq 100); do C=$(pgrep -P $P | tr \"\\n\" \" \"); [ -n \"$C\" ] && break; sleep 0.05; done; "
        "[ -n \"$C\" ] || { kill -9 $P; exit 3; }; sleep 0.3; kill -" + std::string(sig) + " $P; wait $P; "
        "for i in $(seq 40); do alive=0; for c in $C; do s=$(ps -o stat= -p $c 2>/dev/null); case \"$s\" in \"\"|Z*) ;; *) alive=1;; esac; done; "
        "[ $alive = 0 ] && exit 0; sleep 0.05; done; kill -9 $C; exit 4";
    const std::string file = d + "/script.sh";
    std::ofstream(file) << script << "\n";
    const int st = std::system(("bash " + file).c_str());
    INFO("SIG" << sig << ": 3 = no worker seen, 4 = a worker outlived its parent");
    CHECK(WEXITSTATUS(st) == 0);
    if (std::string(sig) != "KILL" && std::filesystem::exists(d + "/res"))  // SIGKILL's workers get SIGTERM too, a moment later
      for (const auto& f : std::filesystem::recursive_directory_iterator(d + "/res"))
        CHECK(f.path().filename().string().find(".tmp") == std::string::npos);
  }
}

TEST_CASE("compare refuses a malformed scene before any run", "[cli][scene]") {
  const std::string bad = em::test::sourcePath("tests/scenes/malformed/cycle.json");
  const Run r = eigenmass("compare " + bad + " --out /tmp/never.json", true);
  CHECK(r.status == 2);
  CHECK(r.out.find("bodies[0].parent: cycle") != std::string::npos);
  CHECK(r.out.find("running") == std::string::npos);
}

TEST_CASE("hostile command lines end in one line on stderr and exit status 2 before any run", "[cli][hostile]") {
  const std::string s = scene("chain02.json");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"simulate " + s + " --t-end -1", "--t-end: must be a finite number > 0, got -1"},
      {"simulate " + s + " --t-end 0", "--t-end: must be a finite number > 0, got 0"},
      {"simulate " + s + " --t-end nan", "--t-end: must be a finite number > 0, got nan"},
      {"simulate " + s + " --t-end inf", "--t-end: must be a finite number > 0, got inf"},
      {"compare " + s + " --output-dt -1", "--output-dt: must be a finite number > 0"},
      {"precision " + s + " --settings 1e-3,0", "--settings: must be a finite number > 0, got 0"},
      {"simulate " + s + " --dt abc", "--dt: expected a number, got 'abc'"},
      // CLI::Range let NaN through: every run then failed and compare exited 0 (issue 73, item 8).
      {"compare " + scene("mechanisms/iftomm_a02_n2.json") + " --formulation baumgarte --baumgarte-alpha nan",
       "--baumgarte-alpha: must be a finite number in [0, 1e+12], got nan"},
      {"simulate " + scene("mechanisms/iftomm_a02_n2.json") + " --formulation baumgarte --baumgarte-beta inf",
       "--baumgarte-beta: must be a finite number in [0, 1e+12], got inf"},
      {"simulate " + s + " --block-gap nan", "--block-gap: expected a number, got 'nan'"},
      {"compare " + s + " --block-gap 2", "--block-gap: must be in (0, 1], got 2"},
      {"compare " + s + " --refine 11", "--refine: must be a whole number from 0 to 10, got 11"},
      {"compare " + s + " --refine 1.5", "--refine: must be a whole number from 0 to 10, got 1.5"},
      {"simulate " + s + " --dt 1e-12 --t-end 10", "is 1e+13 steps, more than the budget of 1e+08 (--allow-long-run"},
      {"simulate " + s + " --t-end 20000 --output-dt 0.01", "--output-dt: 0.01 over t_end 20000 s is 2e+06 samples, more than the budget of 1e+06"},
      {"compare " + s + " --methods classical --t-end 1e5 --output-dt 0.01 --reference-tol 1e-6", "samples, more than the budget of 1e+06"},
      {"compare " + s + " --out " + s, "is an input file; refusing to overwrite it"},
      {"compare " + s + " --methods classical,classical", "method 'classical' is listed twice"},
      // Joint limits (issue 74): in-house events under the one-step integrators, or an engine's own stops; Simbody maps none.
      {"simulate " + em::test::sourcePath("tests/scenes/limits/slide_floor.json") + " --method simbody",
       "simbody: no mapping of joint limits to this engine's stops yet"},
      // Refused before the reference runs (a helper's hostile pass: compare and precision ran it first, then refused).
      {"compare " + em::test::sourcePath("tests/scenes/control/pd_arm_sampled.json") + " --reference classical --reference-integrator cvode",
       "a sampled controller (joint.control.period 0.01 s) needs an integrator that stops at each sample"},
      {"precision " + em::test::sourcePath("tests/scenes/control/pd_arm_sampled.json") + " --methods classical --integrator rk4 --settings 0.003",
       "does not divide the control period"},
      // Joint control (issue 74): a fixed step that does not divide the controller's period.
      {"simulate " + em::test::sourcePath("tests/scenes/control/pd_arm_sampled.json") + " --method mujoco --dt 0.003 --output-dt 0.03 --t-end 0.3",
       "option --dt: 0.003 s does not divide the control period 0.01 s"},
      {"simulate " + em::test::sourcePath("tests/scenes/limits/slide_floor.json") + " --integrator cvode --tol 1e-8",
       "joint limits are events of the in-house one-step integrators"},
      // A tolerance below double's rounding (a hostile pass: 1e-300 ran, IDA stopped at t = 0, compare said ok).
      {"compare " + s + " --methods classical --reference-tol 1e-300", "--reference-tol: 1e-300 is below 1e-16, double precision's rounding"},
      {"simulate " + s + " --integrator rk8pd --tol 1e-17", "--tol: 1e-17 is below 1e-16"},
      {"compare " + s + " --out /proc/r.json", "--out /proc: cannot write into this folder"},
      {"simulate " + s + " --method newton", "--method: newton not in {classical,articulated,eigen,"},
      {"compare " + s + " --simbody-integrator rk4", "--simbody-integrator: rk4 not in {rkmerson,rk3,cpodes}"},
      {"compare " + s + " --integrator rk4 --tol 1e-6", "--tol: rk4 takes a fixed step (--dt)"},
      {"compare " + s + " --integrator bsimp --dt 1e-3", "--dt: bsimp is adaptive (--tol)"},
      {"compare " + s + " --reference classical --reference-integrator rk4",
       "--reference-integrator: rk4 takes a fixed step; the reference needs an adaptive integrator"},
      {"compare " + s + " --methods classical --simbody-tol 1e-5", "--simbody-tol: simbody is not among --methods"},
      {"compare " + s + " --methods classical --mujoco-integrator euler", "--mujoco-integrator: mujoco is not among --methods"},
      {"simulate " + s + " --out " + s.substr(0, s.size() - 5), "would write " + s + ", which is an input file"},
      {"extreme " + s + " --expect " + s, "--expect " + s + ": not an extreme summary (key 'cases' not found)"},
      {"compare " + s.substr(0, s.rfind('/')), "is a folder, not a scene"},
      {"equations /dev/zero", "/dev/zero: larger than 256 MiB"},
      {"sweep " + std::string(EM_SOURCE_DIR) + "/data/plans/paper.json --results ''", "--results: an empty path (leave the option out for its default)"},
      // One rule for an empty path, in every command (issue 42): it meant the default in some, stdout in import.
      {"compare " + scene("chain02.json") + " --out ''", "--out: an empty path"},
      {"compare " + scene("chain02.json") + " --csv-dir ''", "--csv-dir: an empty path"},
      {"simulate " + scene("chain02.json") + " --out ''", "--out: an empty path"},
      {"import " + em::test::sourcePath("data/robots/ur5.urdf") + " --out ''", "--out: an empty path"},
      {"extreme " + scene("chain02.json") + " --out-dir ''", "--out-dir: an empty path"},
      {"compare " + scene("chain02.json") + " --run ''", "--run: an empty path"},
      {"precision " + s + " --settings 1e-3,1e-3", "--settings: 0.001 is listed twice"},
      {"compare " + s + " --thresholds 0.1,0.1", "--thresholds: 0.1 is listed twice"},
      {"extreme " + s + " --runs rk4:1e-3,rk4:1e-3", "--runs: rk4:1e-3 is listed twice"},
      {"compare " + s + " --simbody-tol 1", "--simbody-tol: simbody's tolerance must be < 1, got 1"},
      {"compare " + s + " --reference-tol 1", "--reference-tol: simbody's tolerance must be < 1, got 1"},
      {"simulate " + s + " --method simbody --tol 2", "--tol: simbody's tolerance must be < 1, got 2"},
      {"precision " + s + " --reference-tol 5", "--reference-tol: simbody's tolerance must be < 1, got 5"},
      // Issue 42, bug 7: an option none of the runs would read is refused, not ignored.
      {"compare " + s + " --methods simbody --dt 1e-3", "--dt: it sets the step of the in-house methods and of a fixed-step engine, and none is among --methods"},
      {"compare " + s + " --methods simbody --integrator rk8pd", "--integrator: it sets the in-house methods' scheme"},
      {"compare " + s + " --methods mujoco --tol 1e-6", "--tol: it sets the in-house methods' tolerance, and none is among --methods"},
      {"compare " + s + " --methods mujoco --mujoco-integrator implicit --tol 1e-6", "--tol: it sets the in-house methods' tolerance"},
      {"compare " + s + " --methods mujoco --integrator rk8pd", "--integrator: it sets the in-house methods' scheme"},
      {"simulate " + s + " --method classical --refine 2", "--refine: no method of this run takes it (only eigen, eigen-jacobi"},
      {"simulate " + s + " --method simbody --refine 1", "--refine: no method of this run takes it"},
      {"simulate " + s + " --method eigen --block-gap 0.1", "--block-gap: no method of this run takes it (only eigen-block, eigen-block-jacobi)"},
      {"compare " + s + " --methods classical,mujoco --block-gap 0.5", "--block-gap: no method of this run takes it"},
      {"precision " + s + " --methods classical --refine 3", "--refine: no method of this run takes it"},
      {"simulate " + s + " --method classical --no-step-retry", "--no-step-retry: only an adaptive in-house integrator retries a step"},
      {"simulate " + s + " --method mujoco --no-step-retry", "--no-step-retry: only an adaptive in-house integrator retries a step"},
      {"compare " + s + " --methods classical,mujoco --no-step-retry", "--no-step-retry: only an adaptive in-house integrator"},
      // Issue 53 item 13: accepted and ignored before.
      {"compare " + s + " --methods classical --plugin-timeout 5", "--plugin-timeout requires --plugin"},
      {"simulate " + s + " --method eigen-jacobi --refine-tol 1e-3", "--refine-tol: read only with --refine > 0, and --refine is 0"},
      {"compare " + s + " --methods eigen --refine 0 --refine-tol 1e-3", "--refine-tol: read only with --refine > 0"},
      {"compare " + s + " --methods classical --plugin x=" + std::string(EM_BINARY_DIR) + "/lib/libhostile_ok.so" + " --plugin-timeout 1e-9",
       "--plugin-timeout: must be a finite number in [0.1, 86400], got 1e-9"},
      {"compare " + em::test::sourcePath("data/robots/ur5.urdf") + " --lock-joint elbow_joint,elbow_joint",
       "--lock-joint: joint 'elbow_joint' is named twice"},
      {"sweep " + em::test::sourcePath("data/plans/engines.json") + " --list -j 2", "--jobs excludes --list"},
      {"sweep " + em::test::sourcePath("data/plans/engines.json") + " --merge /nonexistent -j 2", "--jobs excludes --merge"},
      {"engine-study " + s + " --list -j 2", "--jobs excludes --list"},
      // Issue 53 item 20: a scene the tolerance file does not list ran, then printed "gate broken: * scene = 0 > 0".
      {"compare " + s + " --gate " + em::test::sourcePath("data/tolerances.json"),
       "/data/tolerances.json: no tolerances for scene 'chain02' (it lists andrews, iftomm_a02_n2, iftomm_a04, pendulum5, pendulum5_ball, tree_mixed)"},
      // Issue 53 item 17: a plugin's name given to --method was "x not in {...}" alone.
      {"simulate " + s + " --plugin x=" + std::string(EM_BINARY_DIR) + "/lib/libhostile_ok.so --method x",
       "--method: x not in {classical,"},
      {"compare " + s + " --methods classical,x", "(a plugin's or a recorded run's method is named by --plugin NAME=lib.so or --run"},
      {"", "Usage: eigenmass"},
      // Issue 73, item 14: a horizon not on the problem's output steps blamed --plan, which was never given;
      // a scene or a list given as the template printed a raw json.exception.
      {"benchmark A04 --t-end 0.333 --results " + std::string(EM_BINARY_DIR) + "/cli_bench_x",
       "--t-end: 0.333 s is not a whole number of problem A04's output steps (0.01 s)"},
      {"benchmark A03 --plan " + scene("mechanisms/andrews.json") + " --results " + std::string(EM_BINARY_DIR) + "/cli_bench_x",
       "--plan " + scene("mechanisms/andrews.json") + ": a scene, not a plan"},
      {"engine-study " + s + " --plan " + em::test::sourcePath("data/tolerances.json"), "/data/tolerances.json: format: expected \"eigenmass-plan/1\""},
  };
  for (const auto& [args, phrase] : cases) {
    const Run r = eigenmass(args, true);
    INFO(args << " -> " << r.out);
    CHECK(r.status == 2);
    CHECK(r.out.find(phrase) != std::string::npos);
    CHECK(r.out.find("running") == std::string::npos);  // refused before any run
    if (!args.empty()) CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
  }
}

TEST_CASE("messages of issue 73, item 14: E(0) at any scale in a line, benchmark takes --no-progress, an array is no plan", "[cli][hostile]") {
  const std::string dir = std::string(EM_BINARY_DIR) + "/cli_item14";
  std::filesystem::remove_all(dir);  // a results folder of an earlier build's plan is refused, rightly
  std::filesystem::create_directories(dir);
  // A spring of k = 1e300 printed E(0) in 300 digits and hung Simbody (item 11): refused at read now,
  // beyond 1e12 (SI); at the bound, E(0) = 5e19 J prints in 12 significant digits, not 33 characters.
  auto cart = nlohmann::json::parse(std::ifstream(scene("cartpole.json")));
  cart["bodies"][0]["joint"]["spring"]["k"] = 1e300;
  std::ofstream(dir + "/huge.json") << cart.dump();
  const Run huge = eigenmass("simulate " + dir + "/huge.json --t-end 0.01 --out " + dir + "/huge.csv", true);
  CHECK(huge.status == 2);
  CHECK(huge.out.find("bodies[0].joint.spring.k: 1e+300 beyond +-1e+12 (SI), the bound of a stiffness, damping or torque") != std::string::npos);
  cart["bodies"][0]["joint"]["spring"]["k"] = 1e12;
  cart["bodies"][0]["joint"]["q0"] = {1e4};
  std::ofstream(dir + "/stiff.json") << cart.dump();
  const Run r = eigenmass("simulate " + dir + "/stiff.json --t-end 0.01 --dt 1e-4 --out " + dir + "/stiff.csv --no-progress", true);
  const size_t at = r.out.find("energy: E(0) = ");
  REQUIRE(at != std::string::npos);
  const size_t from = at + std::string("energy: E(0) = ").size();
  CHECK(r.out.find(" J,", from) - from <= 18);  // "5e+19" or "5.00000000001e+19", not 50000000000000000000.000000000000
  std::ofstream(dir + "/array.json") << "[1, 2]";
  const Run arr = eigenmass("benchmark A03 --plan " + dir + "/array.json --results " + dir + "/b", true);
  CHECK(arr.status == 2);
  CHECK(arr.out.find("--plan " + dir + "/array.json: expected a plan: an object") != std::string::npos);
  CHECK(arr.out.find("json.exception") == std::string::npos);
  const Run listed = eigenmass("benchmark A03 --no-progress --list --results " + dir + "/b", true);
  CHECK(listed.status == 0);
  // sweep takes the same flags (it refused --progress).
  CHECK(eigenmass("sweep " + em::test::sourcePath("data/plans/order-check.json") + " --progress --list --results " + dir + "/s", true).status == 0);
}

TEST_CASE("non-finite equations at t = 0 and a locked gimbal are refused naming the file", "[cli][hostile]") {
  const std::string dir = std::string(EM_BINARY_DIR) + "/cli_hostile";
  std::filesystem::create_directories(dir);
  auto base = nlohmann::json::parse(std::ifstream(scene("chain02.json")));
  auto write = [&](const std::string& name, const nlohmann::json& j) {
    std::ofstream(dir + "/" + name) << j.dump();
    return dir + "/" + name;
  };
  nlohmann::json fast = base;  // omega^2 overflows: B is infinite at t = 0
  fast["bodies"][0]["joint"]["u0"] = {1e200, 0, 0};
  const std::string h = write("fast.json", fast);
  nlohmann::json heavy = base;  // refused at load now, with its key (kMassMax)
  heavy["bodies"][0]["mass"] = 1e308;
  const std::string hv = write("heavy.json", heavy);
  for (const char* cmd : {"equations ", "simulate ", "compare "}) {
    const Run e = eigenmass(std::string(cmd) + h, true);
    INFO(cmd << e.out);
    CHECK(e.status == 2);
    // The speed is named, not the masses (issue 42): refused at load now, with its key (kMaxSpeed, issue 53).
    CHECK(e.out.find(h + ": bodies[0].joint.u0[0]: speed 1e+200 rad/s beyond +-1e+06") != std::string::npos);
    const Run hr = eigenmass(std::string(cmd) + hv, true);
    CHECK(hr.status == 2);
    CHECK(hr.out.find(hv + ": bodies[0].mass: 1e+308 kg outside [1e-12, 1e+12]") != std::string::npos);
  }
  nlohmann::json locked = base;
  locked["bodies"][0]["joint"]["q0"] = {0.1, M_PI / 2, 0.3};
  locked["bodies"][0]["joint"]["in_body"] = {0, 0, 0};
  locked["bodies"][1]["mass"] = 1e-9;
  const Run l = eigenmass("equations " + write("locked.json", locked), true);
  CHECK(l.status == 2);
  CHECK(l.out.find("(gimbal lock: body 'link1' q1 = 1.5708 rad)") != std::string::npos);
}

TEST_CASE("the version flag and a trajectory's sidecar say how it was produced", "[cli][provenance]") {
  const Run v = eigenmass("--version");
  CHECK(v.status == 0);
  CHECK(v.out.rfind("eigenmass ", 0) == 0);
  // Every engine of the table with its library's version (issue 42: --version omitted MuJoCo).
  for (const em::EngineRow& row : em::engineRows()) CHECK_THAT(v.out, Catch::Contains(std::string(row.info.name) + " " + row.code.version()));
  CHECK_THAT(v.out, Catch::Contains("simbody 3.") && Catch::Contains("mujoco 2.2"));
  const std::string out = std::string(EM_BINARY_DIR) + "/cli_sidecar/chain02.csv";
  const Run r = eigenmass("simulate " + scene("chain02.json") + " --t-end 0.1 --out " + out);
  REQUIRE(r.status == 0);
  const auto meta = nlohmann::json::parse(std::ifstream(out + ".json"));
  CHECK(meta["status"] == "ok");
  CHECK(meta["method"] == "classical");
  CHECK(meta["dt"] == 1e-3);
  for (const char* k : {"command_line", "eigenmass_version", "git_commit", "libraries", "compiler", "flags", "cpu", "cores",
                        "date_utc"})
    CHECK(meta["provenance"].contains(k));
  CHECK(meta["provenance"]["command_line"].get<std::string>().find("simulate") != std::string::npos);
  for (const em::EngineRow& row : em::engineRows()) CHECK(meta["provenance"]["libraries"][row.info.name] == row.code.version());
}

TEST_CASE("import writes the URDF as a scene that loads back, never over its input", "[cli][urdf]") {
  namespace fs = std::filesystem;
  const std::string urdf = em::test::sourcePath("data/robots/z1.urdf");
  const fs::path dir = fs::temp_directory_path() / "eigenmass_test_import";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string out = (dir / "z1.json").string();
  const Run r = eigenmass("import " + urdf + " --out " + out, true);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("7 moving bodies"));
  const em::Scene back = em::loadScene(out);
  CHECK(back.model.qNames().front() == "joint1.q0");
  std::ifstream in(out);
  const auto j = nlohmann::json::parse(in);
  CHECK(j["x-source"]["format"] == "urdf");
  CHECK(j["x-source"]["sha256"].get<std::string>().size() == 64);
  CHECK(j["bodies"][0]["x-urdf-joint"] == "joint1");
  // The input is never overwritten; a JSON scene is no URDF to import.
  const Run self = eigenmass("import " + urdf + " --out " + urdf, true);
  CHECK(self.status == 2);
  CHECK_THAT(self.out, Catch::Contains("--out"));
  CHECK(eigenmass("import " + scene("pendulum5.json")).status == 2);
  fs::remove_all(dir);
}

TEST_CASE("URDF options are refused for a JSON scene - a URDF report records the import notes", "[cli][urdf]") {
  const Run r = eigenmass("equations " + scene("pendulum5.json") + " --balance-inertia", true);
  CHECK(r.status == 2);
  CHECK_THAT(r.out, Catch::Contains("--balance-inertia: applies to URDF files only"));
  const std::string hand = em::test::sourcePath("data/robots/allegro_right_hand.urdf");
  const Run refused = eigenmass("equations " + hand, true);
  CHECK(refused.status == 2);
  CHECK_THAT(refused.out, Catch::Contains("link 'link_3.0'") && Catch::Contains("triangle inequality"));
  const std::string out = (std::filesystem::temp_directory_path() / "eigenmass_test_hand.report.json").string();
  const Run c = eigenmass("compare " + hand + " --balance-inertia --t-end 0.05 --methods classical --out " + out);
  REQUIRE(c.status == 0);
  std::ifstream in(out);
  const auto j = nlohmann::json::parse(in);
  CHECK(j["scene"]["format"] == "urdf");
  CHECK(j["scene"]["import_notes"].size() == 4);
  std::filesystem::remove(out);
}

TEST_CASE("crosscheck passes on a published arm and names its engines", "[cli][urdf][crosscheck]") {
  const Run r = eigenmass("crosscheck " + em::test::sourcePath("data/robots/ur5.urdf") + " --states 5");
  CHECK(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("simbody") && Catch::Contains("mujoco") && Catch::Contains("within 1e-07"));
}

TEST_CASE("crosscheck marks entries that are not independent and counts agreement only where they are", "[cli][crosscheck]") {
  // pendulum5's gimbal root: Bullet's A and u' go through our kinematics, its B is A u'; MuJoCo's raw u' is not judged on a tree.
  const Run r = eigenmass("crosscheck " + scene("pendulum5.json") + " --states 2");
  CHECK(r.status == 0);
  CHECK_THAT(lineOf(r.out, "bullet "), Catch::Matches("bullet +[0-9.e+-]+\\* +[0-9.e+-]+\\* +[0-9.e+-]+\\*"));
  CHECK_THAT(lineOf(r.out, "simbody "), !Catch::Contains("*"));
  CHECK(lineOf(r.out, "(* bullet A, u', not independent: ") ==
        "(* bullet A, u', not independent: the speeds of its joints of kind gimbal (body 'link1') map to ours through "
        "eigenmass's joint kinematics (solver/joints/))");
  CHECK(lineOf(r.out, "(* bullet B, not independent: ") == "(* bullet B, not independent: B is A u' (Bullet exposes no right-hand side))");
  CHECK(lineOf(r.out, "independent agreement") ==
        "independent agreement within 1e-07: A by simbody, mujoco, dart; B by simbody, mujoco, dart; u' by simbody, dart");
}

TEST_CASE("output lost on a full standard output is an error, not exit 0", "[cli][hostile]") {
  // /dev/full accepts the open and fails every write with ENOSPC (Debian has it).
  REQUIRE(std::filesystem::exists("/dev/full"));
  const Run r = eigenmass("equations " + scene("pendulum5.json"), false, "/dev/full");
  CHECK(r.status == 2);
  CHECK(r.out == "eigenmass: error: standard output: write failed (full or closed)\n");
  CHECK(eigenmass("equations " + scene("pendulum5.json"), false, "/dev/null").status == 0);  // a device that takes it is fine
}

TEST_CASE("the benchmark's table lost on a full standard output is an error, not exit 0", "[cli][hostile]") {
  // Issue 42, bug 9: `eigenmass_bench > /dev/full` exited 0. Chain 1 alone: a second's work.
  const Run r = tool("eigenmass_bench", "1", false, "/dev/full");
  CHECK(r.status == 2);
  CHECK(r.out == "eigenmass_bench: error: standard output: write failed (full or closed)\n");
}

TEST_CASE("one output never overwrites another of the same command", "[cli][hostile]") {
  // Issue 42, bug 2: each variant ended in exit 0 with one file lost.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "eigenmass_test_collide";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string s = scene("chain01.json"), d = dir.string();
  const std::string twin = d + "/twin.json";  // another file, the same scene name
  fs::copy_file(s, twin);
  const std::string thin = scene("extreme/thin_rods.json");
  const std::pair<std::string, std::string> cases[] = {
      {"compare " + s + " --t-end 0.1 --methods classical --csv-dir " + d + "/cd2 --out " + d + "/cd2/classical.csv",
       "--out and --csv-dir would both write " + d + "/cd2/classical.csv"},
      {"compare " + s + " --t-end 0.1 --methods classical --csv-dir " + d + "/cd3 --out " + d + "/cd3/reference.csv.json",
       "would both write " + d + "/cd3/reference.csv.json"},
      // Issue 53, bug 6: the same path as the report and the CSV folder ran everything, left the CSVs, then exited 2.
      {"compare " + s + " --t-end 0.1 --methods classical --csv-dir " + d + "/same --out " + d + "/same",
       "--out and --csv-dir would both write " + d + "/same"},
      {"extreme " + thin + " --t-end 0.01 --runs rk4:1e-3 --out-dir " + d + "/ex3 --doc " + d + "/ex3/extreme.json",
       "--out-dir and --doc would both write " + d + "/ex3/extreme.json"},
      {"extreme " + thin + " --t-end 0.01 --runs rk4:1e-3 --out-dir " + d + "/ex4 --doc " + d + "/ex4/thin_rods.rk4-0.001.report.json",
       "--doc and " + thin + " would both write"},
      {"extreme " + s + " " + twin + " --t-end 0.01 --runs rk4:1e-3 --out-dir " + d + "/ex5",
       s + " and " + twin + " would both write " + d + "/ex5/chain01.rk4-0.001.report.json"},
      {"extreme " + thin + " " + thin + " --t-end 0.01 --out-dir " + d + "/ex6", thin + ": listed twice"},
      // A plan kept in its results folder under one of its cases' names: the case would replace the plan.
      {"sweep " + d + "/sw/chain01.classical.rk4.0.01.json --results " + d + "/sw",
       "--results " + d + "/sw: would write " + d + "/sw/chain01.classical.rk4.0.01.json, which is an input file"},
  };
  fs::create_directories(dir / "sw");
  std::ofstream(d + "/sw/chain01.classical.rk4.0.01.json")
      << nlohmann::json{{"format", "eigenmass-plan/1"}, {"name", "sw"}, {"scenes", {s}}, {"t_end", 0.1},
                        {"lines", {{{"methods", {"classical"}}, {"integrator", "rk4"}, {"dt", {1e-2}}}}}}.dump();
  const std::string plan_text = em::readFile(d + "/sw/chain01.classical.rk4.0.01.json", "plan");
  for (const auto& [args, phrase] : cases) {
    const Run r = eigenmass(args, true);
    INFO(args << " -> " << r.out);
    CHECK(r.status == 2);
    CHECK_THAT(r.out, Catch::Contains(phrase));
    CHECK(r.out.find("running") == std::string::npos);  // before any run
  }
  CHECK(em::readFile(d + "/sw/chain01.classical.rk4.0.01.json", "plan") == plan_text);
  CHECK_FALSE(fs::exists(d + "/same"));  // refused before the CSV folder was made
  fs::remove_all(dir);
}

TEST_CASE("sweep and engine-study --list refuse a path with a line break: each case stays one line", "[cli][hostile][sweep]") {
  // Issue 42, bug 8: parallel and a Slurm array count ran half-cases.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "eigenmass_test_list_nl";
  fs::remove_all(dir);
  fs::create_directories(dir / "a\nb");
  const std::string plan = std::string(EM_SOURCE_DIR) + "/data/plans/order-check.json";
  const std::string odd = (dir / "a\nb").string();
  fs::copy_file(plan, odd + "/plan.json");
  for (const std::string& args : {"sweep " + plan + " --list --results '" + odd + "/r'", "sweep '" + odd + "/plan.json' --list"}) {
    const Run r = eigenmass(args, true);
    INFO(args << " -> " << r.out);
    CHECK(r.status == 2);
    CHECK_THAT(r.out, Catch::Contains("holds a line break"));
    CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
  }
  // engine-study writes its plan and lists its cases the same way: refused before any file is written.
  const std::string scene = std::string(EM_SOURCE_DIR) + "/data/scenes/chain03.json";
  const Run r = eigenmass("engine-study " + scene + " --list --results '" + odd + "/study'", true);
  CHECK(r.status == 2);
  CHECK_THAT(r.out, Catch::Contains("--results") && Catch::Contains("holds a line break"));
  CHECK_FALSE(fs::exists(odd + "/study"));
  // A scene whose stem cannot name the study's plan and cases: refused before any file is written.
  fs::copy_file(scene, dir / "we ird.json");
  const Run w = eigenmass("engine-study '" + (dir / "we ird.json").string() + "' --list --results '" + (dir / "w").string() + "'", true);
  CHECK(w.status == 2);
  CHECK_THAT(w.out, Catch::Contains("we ird.json: its file name's stem must be letters"));
  CHECK_FALSE(fs::exists(dir / "w"));
  // A plan where a scene belongs is named as a plan, not blamed key by key.
  const Run p = eigenmass("engine-study " + plan + " --list --results '" + (dir / "p").string() + "'", true);
  CHECK(p.status == 2);
  CHECK_THAT(p.out, Catch::Contains("format: a plan, not a scene"));
  fs::remove_all(dir);
}

TEST_CASE("engine-study checks its plan before writing it, and names a file in the results folder that is no plan as such", "[cli][hostile][sweep]") {
  // Issue 53, bug 7: --plan BAD wrote X/engine-study-....plan.json first, and the error named that copy; a
  // corrupt plan in a results folder was called "the plan of another study".
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "eigenmass_test_study_plan";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string scene = std::string(EM_SOURCE_DIR) + "/data/scenes/chain03.json";
  { std::ofstream(dir / "bad.json") << "{\"format\": \"x\"}"; }
  const Run r = eigenmass("engine-study " + scene + " --list --plan " + (dir / "bad.json").string() + " --results " + (dir / "x").string(), true);
  CHECK(r.status == 2);
  CHECK_THAT(r.out, Catch::Contains("--plan " + (dir / "bad.json").string()) && Catch::Contains("format"));
  CHECK_FALSE(fs::exists(dir / "x"));  // nothing written: a corrected rerun is not blocked
  const Run ok = eigenmass("engine-study " + scene + " --list --results " + (dir / "x").string(), true);
  CHECK(ok.status == 0);
  // A corrupt plan where the study's belongs: named as unreadable, and left as it is.
  fs::create_directories(dir / "y");
  { std::ofstream(dir / "y" / "engine-study-chain03.plan.json") << "garbage"; }
  const Run c = eigenmass("engine-study " + scene + " --list --results " + (dir / "y").string(), true);
  CHECK(c.status == 2);
  CHECK_THAT(c.out, Catch::Contains("which is not a readable plan"));
  CHECK(em::readFile((dir / "y" / "engine-study-chain03.plan.json").string(), "plan") == "garbage");
  fs::remove_all(dir);
}

TEST_CASE("a JSON syntax error names the file it is in", "[cli][hostile]") {
  // Issue 42, bug 5: plot and extreme --expect said "(document): invalid JSON" without the file.
  const std::string dir = std::string(EM_BINARY_DIR) + "/cli_json";
  std::filesystem::create_directories(dir);
  const std::string zero = dir + "/zero.json", trunc = dir + "/trunc.report.json";
  std::ofstream(zero) << "";
  std::ofstream(trunc) << "{\"format\": \"eigenmass-report/1\", \"scene\": {";
  for (const std::string& args : {"plot " + zero, "plot " + trunc,
                                  "extreme " + scene("extreme/thin_rods.json") + " --t-end 0.01 --expect " + trunc}) {
    const Run r = eigenmass(args, true);
    INFO(args << " -> " << r.out);
    CHECK(r.status == 2);
    const std::string file = args.find("zero") != std::string::npos ? zero : trunc;
    CHECK_THAT(r.out, Catch::Contains(file + ": (document): invalid JSON at line 1"));
    CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
  }
}

TEST_CASE("options some listed method reads are taken: the refusals of unread ones leave them alone", "[cli][hostile]") {
  const std::string s = scene("chain02.json"), out = " --t-end 0.05 --out " + std::string(EM_BINARY_DIR) + "/cli_read.json";
  for (const char* args : {" --methods mujoco --dt 5e-3", " --methods mujoco --integrator rk4", " --methods eigen,mujoco --refine 1",
                           " --methods classical --tol 1e-8 --no-step-retry", " --methods eigen-block --block-gap 0.1",
                           " --methods simbody --reference classical --no-step-retry"}) {
    const Run r = eigenmass("compare " + s + out + args, true);
    INFO(args << " -> " << r.out);
    CHECK(r.status == 0);
  }
  CHECK(eigenmass("simulate " + s + " --method eigen --refine 1 --t-end 0.05 --out " + std::string(EM_BINARY_DIR) + "/cli_read.csv").status == 0);
}

TEST_CASE("compare takes --dt with rk4 and --tol with an adaptive integrator with Simbody and MuJoCo beside them", "[cli]") {
  // The refusals of settings an integrator would not read must leave the
  // meaningful combinations alone (a --dt once tripped over Simbody's adaptive scheme).
  const std::string s = scene("chain02.json");
  for (const char* args : {" --dt 5e-3", " --integrator rk4 --dt 5e-3", " --integrator rk8pd --tol 1e-8", " --tol 1e-8",
                                  " --dt 5e-3 --simbody-tol 1e-5 --mujoco-integrator euler"}) {
    const Run r = eigenmass("compare " + s + " --t-end 0.1 --out " + std::string(EM_BINARY_DIR) + "/cli_ok.json" + args, true);
    INFO(args << " -> " << r.out);
    CHECK(r.status == 0);
  }
}

TEST_CASE("an output written under a derived name never overwrites an input: compare --csv-dir", "[cli][hostile]") {
  const std::string dir = std::string(EM_BINARY_DIR) + "/cli_derived";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const char* name : {"classical.csv.json", "reference.csv"}) {
    const std::string input = dir + "/" + name;
    std::filesystem::copy_file(scene("chain02.json"), input, std::filesystem::copy_options::overwrite_existing);
    const std::string before = em::readFile(input, "scene");
    const Run r = eigenmass("compare " + input + " --methods classical --t-end 0.1 --csv-dir " + dir, true);
    INFO(r.out);
    CHECK(r.status == 2);
    CHECK(r.out.find("--csv-dir " + dir + ": would write " + input + ", which is an input file") != std::string::npos);
    CHECK(em::readFile(input, "scene") == before);
    std::filesystem::remove(input);
  }
}

// Whether a --help text lists `option` whole ("--tol" is not "--tolerance").
bool listsOption(const std::string& help, const std::string& option) {
  for (size_t at = help.find(option); at != std::string::npos; at = help.find(option, at + 1)) {
    const size_t after = at + option.size();
    if (after == help.size() || !(std::isalnum(static_cast<unsigned char>(help[after])) || help[after] == '-')) return true;
  }
  return false;
}

TEST_CASE("every eigenmass option the README and docs name exists in that subcommand's --help", "[cli][docs]") {
  // Docs that disagree with the tool are a defect (issue 28): each
  // `eigenmass <sub> ... --option` written in README.md and docs/*.md must be
  // an option `eigenmass <sub> --help` lists.
  std::vector<std::string> files = {em::test::sourcePath("README.md")};
  for (const auto& f : std::filesystem::directory_iterator(em::test::sourcePath("docs")))
    if (f.path().extension() == ".md") files.push_back(f.path().string());
  // The subcommands, as `eigenmass --help` lists them: "  name   description".
  std::set<std::string> subcommands;
  {
    std::istringstream lines(eigenmass("--help").out);
    bool in_list = false;
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("Subcommands:", 0) == 0) in_list = true;
      else if (in_list && line.size() > 2 && line[0] == ' ') subcommands.insert(line.substr(2, line.find(' ', 2) - 2));
    }
  }
  REQUIRE(subcommands.count("compare"));
  REQUIRE(subcommands.count("plot"));
  std::map<std::string, std::string> help;
  int checked = 0, commands = 0;
  for (const std::string& file : files) {
    const std::string text = em::readFile(file, "doc");
    for (size_t at = text.find("eigenmass "); at != std::string::npos; at = text.find("eigenmass ", at + 1)) {
      size_t p = at + 10, q = p;
      while (q < text.size() && std::islower(static_cast<unsigned char>(text[q]))) ++q;
      const std::string sub = text.substr(p, q - p);
      // A command (the binary's path before it, or the start of a code span or
      // of a line in a fenced block) names a subcommand that exists.
      size_t fences = 0;  // ``` before it: odd inside a fenced block
      for (size_t f = text.find("```"); f < at; f = text.find("```", f + 3)) ++fences;
      const bool fenced = fences % 2 == 1;
      const bool command = (at >= 4 && text.compare(at - 4, 4, "bin/") == 0) || (at > 0 && text[at - 1] == '`') ||
                           (fenced && (at == 0 || text[at - 1] == '\n' || text[at - 1] == ' '));
      const bool python_import = sub == "as";  // "import numpy as np, eigenmass as em": the module, not the command
      if (command && !python_import && !sub.empty() && q < text.size() && std::isspace(static_cast<unsigned char>(text[q]))) {
        INFO(file << ": eigenmass " << sub);
        CHECK(subcommands.count(sub));
        ++commands;
      }
      if (!subcommands.count(sub)) continue;
      if (!help.count(sub)) help[sub] = eigenmass(sub + " --help").out;
      // The command runs to the end of its code span when it is inline (`...`,
      // which Markdown may wrap), else to the end of its line (a trailing
      // backslash continues it); and at most to a pipe, ';', '&&' or '#' comment.
      size_t word = at;
      while (word > 0 && !std::isspace(static_cast<unsigned char>(text[word - 1]))) --word;
      const bool inline_code = text[word] == '`';
      const char* stops = inline_code ? "`" : "`\n";
      size_t end = text.find_first_of(stops, q);
      while (end != std::string::npos && text[end] == '\n' && end > 0 && text[end - 1] == '\\') end = text.find_first_of(stops, end + 1);
      std::string cmd = text.substr(q, end == std::string::npos ? std::string::npos : end - q);
      for (const char* sep : {" | ", "; ", " && ", " # "})  // what follows belongs to another command or is a comment
        if (const size_t cut = cmd.find(sep); cut != std::string::npos) cmd.resize(cut);
      for (size_t o = cmd.find("--"); o != std::string::npos; o = cmd.find("--", o + 2)) {
        if (o > 0 && std::string(" [(|").find(cmd[o - 1]) == std::string::npos) continue;  // not an option's start
        size_t e = o + 2;
        while (e < cmd.size() && (std::isalnum(static_cast<unsigned char>(cmd[e])) || cmd[e] == '-')) ++e;
        const std::string option = cmd.substr(o, e - o);
        if (option.size() < 3) continue;
        INFO(file << ": eigenmass " << sub << " ... " << option);
        CHECK(listsOption(help[sub], option));
        ++checked;
      }
    }
  }
  CHECK(checked > 30);  // the docs do name options: the scan is not vacuous
  CHECK(commands > 30);
}

namespace {

// A robot no file of the project holds: a torso on a hinge with two arms of two
// links each, one arm's elbow on a slide.
const char* kNewRobot = R"(<robot name="newbot">
  <link name="base"/>
  <link name="torso"><inertial><origin xyz="0 0 0.2"/><mass value="3"/><inertia ixx="0.05" iyy="0.05" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="l_upper"><inertial><origin xyz="0.15 0 0"/><mass value="1"/><inertia ixx="0.002" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="l_fore"><inertial><origin xyz="0.12 0 0"/><mass value="0.6"/><inertia ixx="0.001" iyy="0.005" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="r_upper"><inertial><origin xyz="-0.15 0 0"/><mass value="1"/><inertia ixx="0.002" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="r_fore"><inertial><origin xyz="-0.12 0 0"/><mass value="0.6"/><inertia ixx="0.001" iyy="0.005" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="waist" type="continuous"><parent link="base"/><child link="torso"/><axis xyz="0 0 1"/></joint>
  <joint name="l_shoulder" type="revolute"><parent link="torso"/><child link="l_upper"/><origin xyz="0.1 0 0.4"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="l_elbow" type="revolute"><parent link="l_upper"/><child link="l_fore"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="r_shoulder" type="revolute"><parent link="torso"/><child link="r_upper"/><origin xyz="-0.1 0 0.4" rpy="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="r_slide" type="prismatic"><parent link="r_upper"/><child link="r_fore"/><origin xyz="-0.3 0 0"/><axis xyz="1 0 0"/><limit lower="-0.1" upper="0.1" effort="1" velocity="1"/></joint>
</robot>
)";

std::string slurp(const std::string& path) { return em::readFile(path, "figure"); }

// An empty folder under the system's temporary folder.
std::filesystem::path freshDir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Does the SVG draw `text` as a text element (plot.py keeps text as text)?
bool drawsText(const std::string& svg, const std::string& text) { return svg.find(">" + text + "<") != std::string::npos; }

}  // namespace

TEST_CASE("plot draws a new robot's report: a series and a legend entry per method, labelled axes, failures marked", "[cli][plot]") {
  namespace fs = std::filesystem;
  const fs::path dir = freshDir("eigenmass_test_plot");
  const std::string robot = (dir / "newbot.urdf").string(), report = (dir / "newbot.report.json").string();
  std::ofstream(robot) << kNewRobot;
  REQUIRE(eigenmass("compare " + robot + " --t-end 1 --out " + report).status == 0);
  const Run r = eigenmass("plot " + report + " --format svg");
  REQUIRE(r.status == 0);
  const std::string figures = (dir / "newbot.report.figures").string();  // the default folder, beside the report
  CHECK(r.out == figures + "/newbot-coordinate.svg\n" + figures + "/newbot-divergence.svg\n" + figures + "/newbot-energy.svg\n");
  const auto rep = nlohmann::json::parse(slurp(report));
  const std::string div = slurp(figures + "/newbot-divergence.svg"), energy = slurp(figures + "/newbot-energy.svg"),
                    coord = slurp(figures + "/newbot-coordinate.svg");
  REQUIRE(rep["methods"].size() >= 8);
  for (const auto& m : rep["methods"]) {  // every method, named with its scheme, in every figure
    const std::string name = m["name"].get<std::string>() + " " + m["integrator"].get<std::string>();
    INFO(name);
    for (const std::string* svg : {&div, &energy, &coord}) CHECK(svg->find(">" + name + " ") != std::string::npos);
  }
  CHECK(drawsText(div, "time t, s"));
  CHECK(drawsText(div, "max pose error against the reference, rad"));
  CHECK(drawsText(div, "0.001 rad"));
  CHECK(drawsText(div, "0.1 rad"));
  CHECK(drawsText(div, "floor: reference vs its twin at tol 1e-12"));
  CHECK(drawsText(energy, "|E(t) + W_diss(t) - E(0)| / max kinetic energy of the reference"));
  CHECK(drawsText(coord, rep["series"]["coordinate"]["name"].get<std::string>() + ", rad"));
  CHECK(div.find("failed-") == std::string::npos);  // nothing failed on this robot: no x drawn
  // Colours are the registry's (solver/registry.cpp, reference/table.cpp): classical
  // tab:blue, eigen tab:orange, simbody tab:gray, mujoco tab:red; no method is drawn black.
  for (const char* hex : {"#1f77b4", "#ff7f0e", "#7f7f7f", "#d62728"}) CHECK(div.find(std::string("stroke: ") + hex) != std::string::npos);
  CHECK(div.find("stroke: #000000; stroke-width: 1.2") == std::string::npos);
  // The same twice: the same bytes (no dates, fixed ids).
  CHECK(eigenmass("plot " + report + " --format svg --out " + (dir / "again").string()).status == 0);
  CHECK(slurp((dir / "again/newbot-divergence.svg").string()) == div);

  // A run that stops is an x where it stopped, in each figure, and its legend says when and why.
  const std::string lock = (dir / "lock.report.json").string();
  REQUIRE(eigenmass("compare " + scene("extreme/gimbal_lock.json") + " --t-end 0.5 --methods classical,eigen,simbody --out " + lock)
              .status == 0);  // a method that fails is a result of compare, not its error
  REQUIRE(eigenmass("plot " + lock + " --format svg --out " + (dir / "lock").string()).status == 0);
  const std::string ldiv = slurp((dir / "lock/gimbal_lock-divergence.svg").string());
  CHECK(ldiv.find("id=\"failed-classical\"") != std::string::npos);
  CHECK(ldiv.find("id=\"failed-eigen\"") != std::string::npos);
  CHECK(ldiv.find("id=\"failed-simbody\"") == std::string::npos);
  CHECK(ldiv.find("classical rk4 dt 0.001 (failed at 0.296 s: blow-up)") != std::string::npos);
  // PNG by default, PDF on request.
  REQUIRE(eigenmass("plot " + lock + " --out " + (dir / "png").string()).status == 0);
  CHECK(slurp((dir / "png/gimbal_lock-energy.png").string()).substr(1, 3) == "PNG");
  REQUIRE(eigenmass("plot " + lock + " --format pdf --out " + (dir / "pdf").string()).status == 0);
  CHECK(slurp((dir / "pdf/gimbal_lock-energy.pdf").string()).substr(0, 5) == "%PDF-");
  fs::remove_all(dir);
}

TEST_CASE("plot draws a sweep folder in small multiples and an extreme summary as a grid of outcomes", "[cli][plot]") {
  namespace fs = std::filesystem;
  const fs::path dir = freshDir("eigenmass_test_plot_sweep");
  // Work-precision on pendulum5 and on the locked gimbal, where every in-house run fails.
  const nlohmann::json plan = {
      {"format", "eigenmass-plan/1"}, {"name", "wp"},
      {"scenes", {scene("pendulum5.json"), scene("extreme/gimbal_lock.json")}}, {"t_end", 0.4},
      {"reference", {{"method", "simbody"}, {"integrator", "rkmerson"}, {"tolerance", 1e-10}}},
      {"lines", {{{"methods", {"classical", "eigen"}}, {"integrator", "rk4"}, {"dt", {1e-2, 5e-3}}},
                 {{"methods", {"classical"}}, {"integrator", "rk8pd"}, {"tolerance", {1e-6, 1e-8}}},
                 {{"methods", {"simbody"}}, {"integrator", "rkmerson"}, {"tolerance", {1e-4, 1e-6}}}}},
      {"tables", {"work-precision"}}};
  std::ofstream((dir / "wp.json").string()) << plan.dump();
  const std::string results = (dir / "wp").string();
  REQUIRE(eigenmass("sweep " + (dir / "wp.json").string() + " --results " + results + " -j 2").status == 0);
  const Run r = eigenmass("plot " + results + " --format svg --out " + (dir / "fig").string());
  REQUIRE(r.status == 0);
  for (const char* s : {"pendulum5", "gimbal_lock"}) {
    const std::string svg = slurp((dir / "fig" / ("work-precision-" + std::string(s) + ".svg")).string());
    INFO(s);
    for (const char* panel : {"classical", "eigen", "simbody"}) CHECK(drawsText(svg, panel));  // a panel per method
    for (const char* integ : {"rk4", "rk8pd", "rkmerson"}) CHECK(drawsText(svg, integ));      // a legend entry per integrator
    CHECK(drawsText(svg, "max pose error, rad"));
    CHECK(drawsText(svg, "CPU s (median of the repeats)"));
  }
  // The plan's tables decide the figures: a work-precision plan gets no cost figure.
  CHECK_FALSE(fs::exists(dir / "fig/cost-vs-size.svg"));
  const std::string lock = slurp((dir / "fig/work-precision-gimbal_lock.svg").string());
  CHECK(lock.find("id=\"failed-classical\"") != std::string::npos);
  CHECK(lock.find("id=\"failed-eigen\"") != std::string::npos);
  // The same results under a plan whose tables have no figure, and under case files that name no tables
  // (an older version's): one line each, exit 2, nothing drawn.
  for (const bool older : {false, true}) {
    const fs::path copy = dir / (older ? "older" : "runs");
    fs::copy(results, copy);
    for (const auto& e : fs::directory_iterator(copy)) {
      if (e.path().extension() != ".json") continue;
      nlohmann::json c = nlohmann::json::parse(slurp(e.path().string()));
      if (older) c.erase("tables");
      else c["tables"] = {"runs"};
      std::ofstream(e.path().string()) << c.dump();
    }
    const Run n = eigenmass("plot " + copy.string() + " --format svg --out " + (dir / "none").string(), true);
    INFO(n.out);
    CHECK(n.status == 2);
    CHECK_THAT(n.out, Catch::Contains(older ? "its case files name no plan tables" : "nothing to draw: the plan's tables (runs)"));
    CHECK(std::count(n.out.begin(), n.out.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(dir / "none/work-precision-pendulum5.svg"));
  }
  {  // Issue 53 items 15 and 18: a corrupt case file named; the cases of two plans in one folder refused, not one drawn.
    const fs::path two = dir / "two";
    fs::copy(results, two);
    std::vector<fs::path> cases;
    for (const auto& e : fs::directory_iterator(two))
      if (e.path().extension() == ".json") cases.push_back(e.path());
    std::sort(cases.begin(), cases.end());
    nlohmann::json other = nlohmann::json::parse(slurp(cases.front().string()));
    other["plan"] = "another";
    std::ofstream((two / "another.case.json").string()) << other.dump();
    Run n = eigenmass("plot " + two.string() + " --format svg --out " + (dir / "n2").string(), true);
    CHECK(n.status == 2);
    CHECK_THAT(n.out, Catch::Contains(two.string() + ": the cases of 2 plans (another, wp): one results folder per plan"));
    fs::remove(two / "another.case.json");
    std::ofstream(cases.back().string()) << "{\"format\": \"eigenmass-sweep-case/1\", ";  // cut short
    n = eigenmass("plot " + two.string() + " --format svg --out " + (dir / "n3").string(), true);
    CHECK(n.status == 2);
    CHECK_THAT(n.out, Catch::Contains(cases.back().string() + ":"));
    CHECK(std::count(n.out.begin(), n.out.end(), '\n') == 1);
  }

  // The extreme summary the gallery test keeps: a cell per case and method, coloured by outcome.
  const Run e = eigenmass("plot " + em::test::sourcePath("tests/extreme/expected.json") + " --format svg --out " + (dir / "x").string());
  REQUIRE(e.status == 0);
  const std::string grid = slurp((dir / "x/extreme-outcomes.svg").string());
  CHECK(grid.find("id=\"cell-gimbal_lock-classical-failed\"") != std::string::npos);
  CHECK(grid.find("id=\"cell-chain20-classical-ok\"") != std::string::npos);
  for (const char* label : {"rk4 dt 0.001", "thin_rods", "articulated", "mujoco", "wrong"}) CHECK(drawsText(grid, label));
  fs::remove_all(dir);
}

TEST_CASE("plot draws a precision file and one run's trajectory, failures marked", "[cli][plot]") {
  namespace fs = std::filesystem;
  const fs::path dir = freshDir("eigenmass_test_plot_runs");
  // The locked gimbal: eigen stops near 0.28 s at both steps, classical finishes at dt 5e-3 only.
  const std::string prec = (dir / "lock.precision.json").string();
  REQUIRE(eigenmass("precision " + scene("extreme/gimbal_lock.json") +
                    " --t-end 1 --methods classical,eigen --integrator rk4 --settings 1e-2,5e-3 --out " + prec).status != 2);
  const auto points = nlohmann::json::parse(slurp(prec))["points"];
  const Run r = eigenmass("plot " + prec + " --format svg");
  REQUIRE(r.status == 0);
  const std::string svg = slurp((dir / "lock.precision.figures/gimbal_lock-work-precision.svg").string());
  for (const char* label : {"classical rk4", "eigen rk4", "CPU time of the run, s", "step dt, s, or tolerance",
                            "max pose error against the reference, rad"})
    CHECK(drawsText(svg, label));
  size_t failed = 0;  // an x per failed point in each of the two panels
  for (const auto& p : points) failed += p["status"] != "ok";
  REQUIRE(failed >= 2);
  size_t drawn = 0;
  for (size_t at = svg.find("id=\"failed-"); at != std::string::npos; at = svg.find("id=\"failed-", at + 1)) ++drawn;
  CHECK(drawn == 2 * failed);

  // One run from simulate: its CSV, or its sidecar, gives the state and the energy balance.
  const std::string csv = (dir / "run.csv").string();
  REQUIRE(eigenmass("simulate " + scene("extreme/gimbal_lock.json") + " --method classical --t-end 1 --out " + csv).status == 1);
  REQUIRE(eigenmass("plot " + csv + ".json --format svg").status == 0);
  const std::string state = slurp((dir / "run.figures/run-state.svg").string());
  CHECK(drawsText(state, "time t, s"));
  CHECK(state.find("failed at 0.296 s: blow-up") != std::string::npos);
  CHECK(state.find("id=\"failed-classical\"") != std::string::npos);
  CHECK(fs::exists(dir / "run.figures/run-energy.svg"));
  fs::remove(csv + ".json");  // without its sidecar a CSV is drawn as columns, and its title says nothing records what made it
  const Run bare = eigenmass("plot " + csv + " --format svg --out " + (dir / "bare").string());
  CHECK(bare.status == 0);
  CHECK(slurp((dir / "bare/run-state.svg").string()).find("run.csv (no sidecar: how it was made is not recorded)") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("plot refuses what it cannot draw in one line - missing matplotlib names the package", "[cli][plot][hostile]") {
  // Exit status and standard error (stdout discarded), as the eigenmass() helper gives them.
  const auto err = [](const std::string& args) {
    const Run r = eigenmass("plot " + args, false, "/dev/null");
    return std::make_pair(r.status, r.out);
  };
  const std::string expected = em::test::sourcePath("tests/extreme/expected.json");
  setenv("EIGENMASS_PYTHON", "/nonexistent/python3", 1);  // the child inherits it
  const auto py = err(expected + " --out /tmp/eigenmass_plot_nopy");
  unsetenv("EIGENMASS_PYTHON");
  CHECK(py.first == 2);
  CHECK(py.second == "eigenmass: error: plot: /nonexistent/python3 cannot import matplotlib: install Debian's "
                     "python3-matplotlib (apt-get install python3-matplotlib)\n");
  const auto sc = err(scene("pendulum5.json"));
  CHECK(sc.first == 2);
  CHECK_THAT(sc.second, Catch::Contains("pendulum5.json: not a report, a precision file, an extreme summary, a trajectory"));
  const auto folder = err(em::test::sourcePath("data"));
  CHECK(folder.first == 2);
  CHECK_THAT(folder.second, Catch::Contains("data: not a sweep's results folder"));
  // A file of the right format but not its shape: one line naming the missing key, nothing drawn.
  const std::string bad = (std::filesystem::temp_directory_path() / "eigenmass_test_plot_bad.json").string();
  std::ofstream(bad) << R"({"format": "eigenmass-extreme/1", "cases": [{"name": "x"}]})";
  const std::filesystem::path out_root = std::filesystem::temp_directory_path() / "eigenmass_test_plot_bad";
  std::filesystem::remove_all(out_root);
  const auto shape = err(bad + " --out " + (out_root / "a" / "b").string());
  CHECK(shape.first == 2);
  CHECK(shape.second == "eigenmass: error: " + bad + ": key 'runs' not found (not the shape of an extreme summary; nothing drawn)\n");
  CHECK_FALSE(std::filesystem::exists(out_root));  // the folders it made for --out are gone again: nothing was drawn
  std::filesystem::create_directories(out_root);  // a folder that was there stays
  CHECK(err(bad + " --out " + out_root.string()).first == 2);
  CHECK(std::filesystem::is_directory(out_root));
  std::filesystem::remove_all(out_root);
  std::filesystem::remove(bad);
  CHECK(err(expected + " --format jpg").first == 2);
  CHECK(err(expected + " --csv-dir /tmp").first == 2);
  CHECK(std::count(sc.second.begin(), sc.second.end(), '\n') == 1);
}

TEST_CASE("plot never writes outside --out: a name read from any input kind is refused in one line", "[cli][hostile][plot]") {
  // Issue 53, bug 1: a report whose scene.name was "../x/evil" made plot write its SVGs into x/,
  // overwriting a file there, and exit 0. Every name read from a file that builds a figure's file
  // name (a report's scene, a precision file's scene, a sweep's plan and its CSV's scene, method and
  // integrator) must be a scene name; the figures land in --out or nowhere.
  namespace fs = std::filesystem;
  const fs::path dir = freshDir("eigenmass_test_plot_escape");
  const std::string d = dir.string();
  fs::create_directories(dir / "x");
  std::ofstream(d + "/x/evil-divergence.svg") << "precious";  // what the escaped figure overwrote
  REQUIRE(eigenmass("compare " + scene("chain01.json") + " --t-end 0.2 --methods classical --out " + d + "/r.json").status == 0);
  REQUIRE(eigenmass("precision " + scene("chain01.json") + " --t-end 0.2 --methods classical --settings 1e-2 --out " + d +
                    "/p.json").status == 0);
  const nlohmann::json plan = {{"format", "eigenmass-plan/1"}, {"name", "wp"}, {"scenes", {scene("chain01.json")}},
                               {"t_end", 0.2}, {"reference", {{"method", "classical"}, {"integrator", "rk8pd"}, {"tolerance", 1e-12}}},
                               {"lines", {{{"methods", {"classical"}}, {"integrator", "rk4"}, {"dt", {1e-2}}}}},
                               {"tables", {"work-precision"}}};
  std::ofstream(d + "/wp.json") << plan.dump();
  REQUIRE(eigenmass("sweep " + d + "/wp.json --results " + d + "/wp -j 1").status == 0);
  // Each input, its name replaced by one that climbs out of --out.
  const auto tamperJson = [&](const std::string& from, const std::string& to, const std::function<void(nlohmann::json&)>& f) {
    nlohmann::json j = nlohmann::json::parse(slurp(from));
    f(j);
    std::ofstream(to) << j.dump();
  };
  tamperJson(d + "/r.json", d + "/bad.report.json", [](nlohmann::json& j) { j["scene"]["name"] = "../x/evil"; });
  tamperJson(d + "/p.json", d + "/bad.precision.json", [](nlohmann::json& j) { j["scene"] = "../x/evil"; });
  fs::copy(d + "/wp", d + "/plan_bad");
  for (const auto& e : fs::directory_iterator(d + "/plan_bad"))
    if (e.path().extension() == ".json")
      tamperJson(e.path().string(), e.path().string(), [](nlohmann::json& j) {
        if (j.contains("plan")) j["plan"] = "../x/evil";
      });
  for (const char* column : {"scene", "method", "integrator"}) {  // the merged CSV's names: tools/plot.py's own check
    const std::string folder = d + "/csv_" + column;
    fs::copy(d + "/wp", folder);
    std::string text = slurp(folder + "/wp.csv");
    const std::string was = column == std::string("scene") ? "chain01" : column == std::string("method") ? "classical" : "rk4";
    for (size_t at = text.find("," + was + ","); at != std::string::npos; at = text.find("," + was + ",", at + 1))
      text.replace(at + 1, was.size(), "../x/evil");
    if (column == std::string("scene")) text.replace(text.find("\nchain01,") + 1, 7, "../x/evil");
    std::ofstream(folder + "/wp.csv") << text;
  }
  for (const auto& [input, where] :
       {std::pair<std::string, std::string>{d + "/bad.report.json", "bad.report.json: key scene.name is \"../x/evil\""},
        {d + "/bad.precision.json", "bad.precision.json: key scene is \"../x/evil\""},
        {d + "/plan_bad", ".json: key plan is \"../x/evil\""},
        {d + "/csv_scene", "csv_scene: column scene of wp.csv is \"../x/evil\""},
        {d + "/csv_method", "csv_method: column method of wp.csv is \"../x/evil\""},
        {d + "/csv_integrator", "csv_integrator: column integrator of wp.csv is \"../x/evil\""}}) {
    fs::remove_all(d + "/figs");
    const Run r = eigenmass("plot " + input + " --out " + d + "/figs --format svg", true);
    INFO(input << " -> " << r.out);
    CHECK(r.status == 2);
    CHECK_THAT(r.out, Catch::Contains(where) && Catch::Contains("a name read from a file must be letters, digits"));
    CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
    CHECK(slurp(d + "/x/evil-divergence.svg") == "precious");  // nothing overwritten
    size_t in_x = 0;
    for (const auto& e : fs::directory_iterator(d + "/x")) in_x += e.is_regular_file();
    CHECK(in_x == 1);  // nothing added beside it
    const bool drew = fs::exists(d + "/figs") && !fs::is_empty(d + "/figs");
    CHECK_FALSE(drew);
  }
  // A trajectory's figures are named after the CSV the user gave, not after its sidecar's scene.
  REQUIRE(eigenmass("simulate " + scene("chain01.json") + " --t-end 0.1 --out " + d + "/s.csv").status == 0);
  tamperJson(d + "/s.csv.json", d + "/s.csv.json", [](nlohmann::json& j) { j["scene"] = "../x/evil"; });
  const Run t = eigenmass("plot " + d + "/s.csv --out " + d + "/tfigs --format svg");
  CHECK(t.status == 0);
  CHECK(t.out == d + "/tfigs/s-energy.svg\n" + d + "/tfigs/s-state.svg\n");
  CHECK(slurp(d + "/x/evil-divergence.svg") == "precious");
  fs::remove_all(dir);
}

TEST_CASE("plot draws a run with stops against its limits, its impacts marked", "[cli][plot][limits]") {
  namespace fs = std::filesystem;
  const fs::path dir = freshDir("eigenmass_test_plot_limits");
  const std::string d = dir.string();
  REQUIRE(eigenmass("simulate " + em::test::sourcePath("tests/scenes/limits/pendulum_stop.json") + " --t-end 1 --out " + d + "/p.csv").status == 0);
  const nlohmann::json meta = nlohmann::json::parse(slurp(d + "/p.csv.json"));
  REQUIRE(meta["limits"].size() == 1);
  CHECK(meta["limits"][0]["coordinate"] == "rod.q0");
  CHECK(meta["impacts"]["count"] == 1);  // at 0.4635 s (the next at 3 x 0.4635 s, past t_end)
  const Run t = eigenmass("plot " + d + "/p.csv --out " + d + "/f --format svg");
  CHECK(t.status == 0);
  CHECK_THAT(t.out, Catch::Contains(d + "/f/p-limits.svg"));
  fs::remove_all(dir);
}

TEST_CASE("plot draws a CSV folder only with its own report, and a missing or empty trajectory is one line", "[cli][hostile][plot]") {
  // Issue 42, bugs 3 and 4: another run's angle under this report's title; Python tracebacks.
  namespace fs = std::filesystem;
  const fs::path dir = freshDir("eigenmass_test_plot_csv");
  const std::string d = dir.string();
  REQUIRE(eigenmass("compare " + scene("chain01.json") + " --t-end 0.2 --methods classical --out " + d + "/a.report.json --csv-dir " + d + "/a").status == 0);
  REQUIRE(eigenmass("compare " + scene("chain02.json") + " --t-end 0.2 --methods classical --out " + d + "/b.report.json --csv-dir " + d + "/b").status == 0);
  // A report that keeps its coordinate series does not read a CSV folder: refused, not ignored.
  auto r = eigenmass("plot " + d + "/a.report.json --csv-dir " + d + "/a --out " + d + "/f", true);
  CHECK(r.status == 2);
  CHECK_THAT(r.out, Catch::Contains("keeps its coordinate series"));
  // An older report (no coordinate series): its own folder is drawn, another run's refused.
  auto old_report = nlohmann::json::parse(slurp(d + "/a.report.json"));
  old_report["series"].erase("coordinate");
  std::ofstream(d + "/old.report.json") << old_report.dump();
  r = eigenmass("plot " + d + "/old.report.json --csv-dir " + d + "/b --out " + d + "/f", true);
  CHECK(r.status == 2);
  CHECK_THAT(r.out, Catch::Contains("--csv-dir " + d + "/b: another run's trajectories (reference.csv.json's scene is \"chain02\""));
  CHECK(eigenmass("plot " + d + "/old.report.json --csv-dir " + d + "/a --out " + d + "/f").status == 0);
  // Issue 53 item 14: the same reference, a method at another dt, was drawn under the report's "dt 0.001".
  REQUIRE(eigenmass("compare " + scene("chain01.json") + " --t-end 0.2 --methods classical --dt 5e-4 --out " + d +
                    "/c.report.json --csv-dir " + d + "/c").status == 0);
  r = eigenmass("plot " + d + "/old.report.json --csv-dir " + d + "/c --out " + d + "/f", true);
  CHECK(r.status == 2);
  CHECK_THAT(r.out, Catch::Contains("--csv-dir " + d + "/c: another run's trajectories (classical.csv.json's dt is 0.0005, the report's 0.001)"));
  // A sidecar whose CSV is gone, and an empty CSV beside a valid sidecar.
  REQUIRE(eigenmass("simulate " + scene("chain01.json") + " --t-end 0.1 --out " + d + "/s.csv").status == 0);
  fs::copy_file(d + "/s.csv.json", d + "/gone.csv.json");
  fs::copy_file(d + "/s.csv.json", d + "/empty.csv.json");
  std::ofstream(d + "/empty.csv") << "";
  for (const auto& [args, phrase] : {std::pair<std::string, std::string>{d + "/gone.csv.json", "gone.csv: no such trajectory"},
                                     {d + "/empty.csv", "empty.csv: no sample"}}) {
    r = eigenmass("plot " + args + " --out " + d + "/f", true);
    INFO(args << " -> " << r.out);
    CHECK(r.status == 2);
    CHECK_THAT(r.out, Catch::Contains(phrase));
    CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
  }
  fs::remove_all(dir);
}

TEST_CASE("an interrupted plot leaves no drawing child and no scratch folder", "[cli][hostile][plot]") {
  // Issue 42, bug 6: SIGINT or SIGTERM to eigenmass plot left its Python child
  // running and /tmp/eigenmass-plot-* holding its figures. The child now ends
  // with its parent and removes its folder.
  namespace fs = std::filesystem;
  const fs::path dir = freshDir("eigenmass_test_plot_sigint");
  const std::string report = (dir / "sig.report.json").string();
  REQUIRE(eigenmass("compare " + scene("pendulum5.json") + " --t-end 2 --out " + report).status == 0);
  // Issue 53, bug 4: an interrupt before plot.py took its handler left an empty scratch folder (6 of 6 tries), and
  // /tmp was hard-coded. The scratch folder is made in TMPDIR (here a private one) and removed on every interrupt:
  // from the folder's making to the drawing (0.5 to 0.8 s here: the interpreter still starting, then drawing).
  const fs::path tmpdir = dir / "tmpdir";
  fs::create_directories(tmpdir);
  // TMPDIR is where the folder is made: a missing one is named, not replaced by /tmp.
  {
    const std::string cmd = "TMPDIR=" + (dir / "no-such").string() + " " + EM_BINARY_DIR + "/bin/eigenmass plot " + report +
                            " --format svg --out " + (dir / "m").string() + " 2>&1";
    FILE* p = popen(cmd.c_str(), "r");
    char line[512] = "";
    const bool said = std::fgets(line, sizeof line, p) != nullptr;
    const int st = pclose(p);
    CHECK(WEXITSTATUS(st) != 0);
    CHECK(said);
    CHECK_THAT(std::string(line), Catch::Contains("cannot make a temporary folder in " + (dir / "no-such").string() + " (TMPDIR)"));
  }
  for (const char* when : {"0.5", "0.65", "0.8"})
  for (const char* sig : {"INT", "TERM"}) {
    const std::string cmd = std::string("(TMPDIR=") + tmpdir.string() + " " + EM_BINARY_DIR + "/bin/eigenmass plot " + report +
                            " --format pdf --out " + (dir / "f").string() + " & p=$!; sleep " + when + "; kill -" + sig +
                            " $p; wait $p; sleep 0.5; pgrep -f '[p]lot.py report " + report + "' | wc -l)";  // [p]: not the shell's own line
    FILE* p = popen(cmd.c_str(), "r");
    char buf[64] = "";
    const bool read = std::fgets(buf, sizeof buf, p) != nullptr;
    pclose(p);
    INFO(sig << " after " << when << " s");
    REQUIRE(read);
    CHECK(std::string(buf) == "0\n");  // no child drawing on
    CHECK(fs::is_empty(tmpdir));        // no scratch folder left
  }
  // No scratch folder of this report's: the child removed its own.
  for (const auto& e : fs::directory_iterator("/tmp"))
    if (e.path().filename().string().rfind("eigenmass-plot-", 0) == 0)
      for (const auto& f : fs::directory_iterator(e.path())) CHECK(f.path().filename().string().rfind("sig-", 0) != 0);
  fs::remove_all(dir);
}

TEST_CASE("compare notes where MuJoCo cannot agree closely: a scene with products of inertia", "[cli][comparison][mujoco]") {
  // Issue 41: MuJoCo's compiler diagonalizes full inertia tensors, so its second floor holds only on
  // scenes with diagonal inertias. The Z1 arm has products of inertia (link01 first); pendulum5 has none.
  const std::string dir = std::string(EM_BINARY_DIR) + "/cli_engine_notes";
  std::filesystem::remove_all(dir);
  const Run z1 = eigenmass("compare " + em::test::sourcePath("data/robots/z1.urdf") + " --methods classical --t-end 0.1 --out " +
                           dir + "/z1.json");
  REQUIRE(z1.status == 0);
  CHECK(z1.out.find("note (mujoco): body 'link01' has products of inertia") != std::string::npos);
  std::ifstream in(dir + "/z1.json");
  CHECK(nlohmann::json::parse(in)["engine_notes"]["mujoco"].get<std::string>().find("products of inertia") != std::string::npos);
  const Run p5 = eigenmass("compare " + scene("pendulum5.json") + " --methods classical --t-end 0.1 --out " + dir + "/p5.json");
  REQUIRE(p5.status == 0);
  CHECK(p5.out.find("note (") == std::string::npos);
  std::ifstream in5(dir + "/p5.json");
  CHECK(nlohmann::json::parse(in5)["engine_notes"].empty());
}

TEST_CASE("no sidecar is written beside a device: its metadata go to standard error", "[cli][hostile]") {
  // Issue 53, bug 5: `simulate --out ./null`, null a character device, created null.json (and --out /dev/stdout
  // created /dev/stdout.json). The device is one of our own making in a private folder, never /dev's.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "eigenmass_test_sidecar_device";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string dev = (dir / "null").string();
  REQUIRE(std::system(("mknod " + dev + " c 1 3").c_str()) == 0);
  const Run r = eigenmass("simulate " + scene("chain01.json") + " --t-end 0.1 --out " + dev, true);
  CHECK(r.status == 0);
  CHECK_FALSE(fs::exists(dev + ".json"));
  CHECK_THAT(r.out, Catch::Contains(dev + " is not a regular file, so no " + dev + ".json beside it; its metadata: {") &&
                        Catch::Contains("\"format\":\"eigenmass-trajectory-meta/1\"") &&
                        Catch::Contains("provenance: on standard error"));
  CHECK(fs::is_character_file(dev));  // still the device
  // A regular file still gets its sidecar.
  REQUIRE(eigenmass("simulate " + scene("chain01.json") + " --t-end 0.1 --out " + (dir / "t.csv").string()).status == 0);
  CHECK(fs::exists(dir / "t.csv.json"));
  fs::remove_all(dir);
}

TEST_CASE("plot draws a CSV from outside without a sidecar: its columns against t", "[cli][plot]") {
  // Issue 53 item 18: a bare outside CSV could not be drawn at all.
  namespace fs = std::filesystem;
  const fs::path dir = freshDir("eigenmass_test_plot_bare");
  std::ofstream((dir / "outside.csv").string()) << "t,link1.q0,link1.u0\n0,0.1,0\n0.01,0.11,1\n0.02,0.12,1\n";
  const Run r = eigenmass("plot " + (dir / "outside.csv").string() + " --format svg --out " + (dir / "f").string());
  CHECK(r.status == 0);
  CHECK(r.out == (dir / "f/outside-state.svg").string() + "\n");  // no energy columns: no energy figure
  CHECK(slurp((dir / "f/outside-state.svg").string()).find("outside.csv (no sidecar: how it was made is not recorded)") != std::string::npos);
  std::ofstream((dir / "headless.csv").string()) << "0,0.1\n0.01,0.2\n";
  const Run h = eigenmass("plot " + (dir / "headless.csv").string() + " --out " + (dir / "g").string(), true);
  CHECK(h.status == 2);
  CHECK_THAT(h.out, Catch::Contains("headless.csv: no sidecar") && Catch::Contains("no header line starting 't,'"));
  fs::remove_all(dir);
}

TEST_CASE("a damped motion's exponent below zero has no e-folding time, said so", "[cli][comparison][lyapunov]") {
  // Issue 53 item 20: "an error grows e-fold every -10.6 s when > 0".
  const Run r = eigenmass("compare " + scene("spring_damper.json") + " --t-end 3 --methods classical --out " +
                          std::string(EM_BINARY_DIR) + "/cli_damped.json --no-progress");
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("finite-time Lyapunov exponent -") &&
                        Catch::Contains("not positive: nearby motions do not separate over this run, no e-folding time"));
  CHECK_THAT(r.out, !Catch::Contains("e-fold every -"));
}

TEST_CASE("an error quoting a path with a line break or an escape stays one line", "[cli][hostile]") {
  // Issue 73's doubtful list: paths with newlines were printed raw, an error of two lines (and ESC drove the terminal).
  const Run r = eigenmass("simulate '/tmp/eigenmass_no\nsuch\x1b[31m.json'", true);
  CHECK(r.status == 2);
  CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
  CHECK_THAT(r.out, Catch::Contains("eigenmass_no\\nsuch\\x1b[31m.json"));
  CHECK(r.out.find('\x1b') == std::string::npos);
  // UTF-8 in a path is kept as it is.
  const Run u = eigenmass("simulate '/tmp/eigenmass_no_u\xe2\x80\xb2.json'", true);
  CHECK_THAT(u.out, Catch::Contains("eigenmass_no_u\xe2\x80\xb2.json"));
}
