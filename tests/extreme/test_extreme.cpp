// The extreme-case gallery: its scenes are what they claim (closed forms and
// Simbody), its settings and keys are validated, and its diagnosis and its
// check against a recorded summary say what the numbers say.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "compare/crosscheck.hpp"
#include "extreme/extreme.hpp"
#include "solver/formation.hpp"
#include "support.hpp"

using namespace em;

namespace {

std::string readText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string gallery(const std::string& name) { return test::sourcePath("data/scenes/extreme/" + name + ".json"); }

// Eigenvalue gap of the two-link scene's A at elbow angle q2 (q1 plays no part: no gravity).
double gapAt(const Model& m, double q2) {
  Workspace ws(m);
  Eigen::VectorXd q = m.q0(), u = Eigen::VectorXd::Zero(m.nu);
  q[1] = q2;
  formEquations(m, q.data(), u.data(), ws);
  const Eigen::Vector2d l = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(ws.A).eigenvalues();
  return l[1] - l[0];
}

// Golden-section minimum of gapAt on [a, b].
double minGap(const Model& m, double a, double b) {
  const double r = (std::sqrt(5.0) - 1) / 2;
  for (int k = 0; k < 200; ++k) {
    const double x1 = b - r * (b - a), x2 = a + r * (b - a);
    (gapAt(m, x1) < gapAt(m, x2) ? b : a) = gapAt(m, x1) < gapAt(m, x2) ? x2 : x1;
  }
  return gapAt(m, (a + b) / 2);
}

ExtremeEntry failedEntry(Failure kind) {
  ExtremeEntry e;
  e.method = "eigen";
  e.outcome = Outcome::Failed;
  e.failure_kind = kind;
  e.failure_time = 0.5;
  e.eigenfactor = true;
  e.eigen.min_gap = 1e-6;
  e.eigen.min_gap_time = 0.4;
  e.eigen.max_abs_Omega = 3e5;
  return e;
}

}  // namespace

TEST_CASE("near_crossing: the eigenvalues of A pass within 1e-6 of each other, as tuned", "[closedform][extreme]") {
  // tools/make_extreme.py puts link 2's inertia about its joint, K2, eps above
  // the value of an exact crossing; the gap's minimum over the elbow angle is
  // then sqrt(2) eps, set to 1e-6, near cos q2 = -K2 / (m2 l1 a2), q2 = 2.40 rad.
  const Model m = loadScene(gallery("near_crossing")).model;
  const double gap = minGap(m, 2.2, 2.6);
  CHECK(gap == Approx(1e-6).epsilon(1e-6));
  CHECK(gapAt(m, 1.0) > 0.1);  // far from it, the gap is of the order of the eigenvalues
}

TEST_CASE("gallery scenes: cond(A) at t = 0 as each x-why says", "[extreme]") {
  auto cond0 = [](const std::string& name) {
    const Model m = loadScene(gallery(name)).model;
    Workspace ws(m);
    formEquations(m, m.q0().data(), m.u0().data(), ws);
    return conditionNumber(ws.A);
  };
  CHECK(cond0("mass_falling") >= 1e8);
  CHECK(cond0("thin_rods") >= 1e11);
  CHECK(cond0("near_crossing") < 100);
}

TEST_CASE("gallery scenes: A and B agree with Simbody at the initial and at random states", "[crosscheck][extreme]") {
  // The formation must be right on every hard case before any method is
  // judged on it; bound as the data scenes' (round-off, measured <= 1e-15).
  constexpr double kRoundOff = 1e-12;
  int scenes = 0, rows = 0;
  for (const auto& f : std::filesystem::directory_iterator(test::sourcePath("data/scenes/extreme"))) {
    const Scene scene = loadScene(f.path().string());
    const CrossCheck c = crossCheck(scene, {}, 3, 7);
    ++scenes;
    for (const CrossCheckRow& row : c.rows) {
      if (row.engine != "simbody") continue;
      ++rows;
      INFO(scene.model.name << " state " << row.state << ": A " << row.A << " B " << row.B);
      CHECK(row.A <= kRoundOff);
      CHECK(row.B <= kRoundOff);
    }
  }
  CHECK(scenes == 17);  // 15 trees and two mechanisms (A and B are the tree's: the loops add G, checked in test_crosscheck)
  CHECK(rows == 4 * scenes);  // the initial state and three random ones, each
}

TEST_CASE("parseSetting reads integrator:value and refuses anything else", "[extreme]") {
  const ExtremeSetting s = parseSetting("rk8pd:1e-10");
  CHECK(s.integrator == Integrator::RK8PD);
  CHECK(s.value == 1e-10);
  CHECK(s.key() == "rk8pd:1e-10");
  CHECK(s.label() == "rk8pd tol 1e-10");
  CHECK(parseSetting("rk4:1e-3").label() == "rk4 dt 0.001");
  for (const char* bad : {"rk4", "rk4:", "rk4:0", "rk4:-1", "rk4:1e-3x", "rk4:nan", "nope:1e-3", "rkmerson:1e-6"}) {
    INFO(bad);
    CHECK_THROWS_AS(parseSetting(bad), std::invalid_argument);
  }
}

TEST_CASE("x-extreme is validated, naming the file and the key", "[extreme]") {
  const std::string dir = (std::filesystem::temp_directory_path() / "em_extreme_test").string();
  std::filesystem::create_directories(dir);
  auto errorOf = [&](const std::string& extreme) {
    std::string text = readText(gallery("near_crossing"));
    const size_t at = text.find("\"x-extreme\"");
    REQUIRE(at != std::string::npos);
    text = text.substr(0, at) + "\"x-extreme\": " + extreme + ",\n  \"x-end\": 0\n}\n";
    const std::string path = dir + "/case.json";
    std::ofstream(path) << text;
    try {
      loadExtremeCase(path);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_THAT(errorOf("{\"runs\": [\"rk4:1e-3\", \"rk4:0\"]}"), Catch::Contains("case.json: x-extreme.runs[1]: 'rk4:0'"));
  CHECK_THAT(errorOf("{\"runs\": []}"), Catch::Contains("case.json: x-extreme.runs: expected a non-empty list"));
  CHECK_THAT(errorOf("{\"reference_tol\": -1}"), Catch::Contains("case.json: x-extreme.reference_tol: must be a finite number > 0"));
  CHECK_THAT(errorOf("{\"run\": [\"rk4:1e-3\"]}"), Catch::Contains("case.json: x-extreme.run: unknown key"));
  CHECK_THAT(errorOf("{\"reference_integrator\": \"rk4\"}"),
             Catch::Contains("case.json: x-extreme.reference_integrator: 'rk4' is not an in-house adaptive integrator (rkf45, rk8pd, bsimp, ida, cvode)"));
  CHECK_THAT(errorOf("{\"reference_integrator\": \"rkmerson\"}"), Catch::Contains("'rkmerson' is not an in-house adaptive integrator"));
  // The singular four-bars' reference passes the singular positions: rk8pd with the projection, not ida.
  const ExtremeCase singular = loadExtremeCase(gallery("singular_fourbars"));
  REQUIRE(singular.reference_integrator);
  CHECK(*singular.reference_integrator == Integrator::RK8PD);
  CHECK(singular.scene.model.loop_rows == 6);
  const ExtremeCase ok = loadExtremeCase(gallery("stiff_springs"));
  REQUIRE(ok.settings.size() == 3);
  CHECK(ok.settings[2].integrator == Integrator::BSIMP);
  CHECK_FALSE(ok.why.empty());
}

TEST_CASE("the diagnosis of a failure follows its kind and its diagnostics", "[extreme]") {
  ExtremeCaseResult c;
  c.lambda_max0 = 1.0;
  c.cond_A0 = 10;
  ExtremeRun run;
  // A gap of 1e-6 of the largest eigenvalue: a near-crossing, said as such.
  ExtremeEntry e = failedEntry(Failure::NonPositiveEigenvalue);
  CHECK_THAT(diagnosis(e, c, run), Catch::Contains("after a near-crossing") && Catch::Contains("gap 1e-06"));
  // A small gap with slowly turning eigenvectors is no near-crossing.
  e.eigen.max_abs_Omega = 1.0;
  CHECK_THAT(diagnosis(e, c, run), !Catch::Contains("near-crossing"));
  e.eigen.max_abs_Omega = 3e5;
  // The same kind with a wide gap and an ill-conditioned A: conditioning, not a crossing.
  e.eigen.min_gap = 0.5;
  e.failure_cond_A = 1e9;
  CHECK_THAT(diagnosis(e, c, run), Catch::Contains("1/1e+09 of the largest") && !Catch::Contains("near-crossing"));
  // Neither: the step.
  e.failure_cond_A = 10;
  CHECK_THAT(diagnosis(e, c, run), Catch::Contains("step was too large"));
  CHECK_THAT(diagnosis(failedEntry(Failure::JacobiNotConverged), c, run), Catch::Contains("orthogonal"));
  ExtremeEntry wrong = failedEntry(Failure::None);
  wrong.outcome = Outcome::Wrong;
  wrong.wrong_at = 1.9;
  run.horizon_wrong = 4.0;
  CHECK_THAT(diagnosis(wrong, c, run), Catch::Contains("at 1.9 s, before the reference horizon 4 s"));
  ExtremeEntry ok = failedEntry(Failure::None);
  ok.outcome = Outcome::Ok;
  CHECK(diagnosis(ok, c, run).empty());
}

TEST_CASE("checkExpected finds every changed outcome or failure kind, and nothing else", "[extreme]") {
  ExtremeCaseResult c;
  c.name = "case";
  ExtremeRun run;
  run.t_end = 1;
  run.entries = {failedEntry(Failure::EigenGap)};
  c.runs = {run};
  const nlohmann::json recorded = extremeJson({c});
  CHECK(checkExpected({c}, recorded).empty());
  ExtremeCaseResult changed = c;
  changed.runs[0].entries[0].failure_kind = Failure::NonPositiveEigenvalue;
  const auto diff = checkExpected({changed}, recorded);
  REQUIRE(diff.size() == 1);
  CHECK_THAT(diff[0], Catch::Contains("failed (eigenvalue-nonpositive), expected failed (eigen-gap)"));
  changed = c;
  changed.runs[0].t_end = 2;
  CHECK_THAT(checkExpected({changed}, recorded).at(0), Catch::Contains("made with t_end 1"));
  changed = c;
  changed.name = "other";
  CHECK_THAT(checkExpected({changed}, recorded).at(0), Catch::Contains("not in the expected file"));
}
