// outside/recorded.cpp: a run made elsewhere, read from CSV. The oracle is the
// in-house run itself: written out and read back, it must give the run's own
// metrics; every malformed file ends in one line naming file, line and column.
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <filesystem>
#include <fstream>

#include <catch2/catch.hpp>

#include "compare/comparison.hpp"
#include "compare/engines.hpp"
#include "io/csv.hpp"
#include "outside/recorded.hpp"
#include "solver/integrate.hpp"
#include "support.hpp"

using namespace em;

namespace {

std::string tempDir() {
  const std::string d = std::string(EM_BINARY_DIR) + "/outside-tests";
  std::filesystem::create_directories(d);
  return d;
}

std::string writeText(const std::string& name, const std::string& text) {
  const std::string path = tempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

int g_runs = 0;
// A fresh method name per file read (the registry keeps every row).
std::string freshName() { return "rec" + std::to_string(++g_runs); }

// The run's CSV with only the columns `keep` says (by name predicate).
template <class Keep>
std::string csvWith(const Trajectory& tr, const std::string& name, Keep keep, size_t every = 1, double t_max = 1e300) {
  const std::string full = tempDir() + "/full-" + name;
  writeCsv(tr, full);
  std::ifstream in(full);
  std::string header;
  std::getline(in, header);
  std::vector<std::string> cols;
  std::stringstream hs(header);
  for (std::string c; std::getline(hs, c, ',');) cols.push_back(c);
  std::ostringstream out;
  const auto row = [&](const std::vector<std::string>& f) {
    bool first = true;
    for (size_t c = 0; c < f.size(); ++c)
      if (keep(cols[c])) out << (first ? "" : ",") << f[c], first = false;
    out << '\n';
  };
  row(cols);
  size_t k = 0;
  for (std::string line; std::getline(in, line); ++k) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) f.push_back(c);
    if (k % every == 0 && std::stod(f[0]) <= t_max + 1e-12) row(f);
  }
  return writeText(name, out.str());
}

const auto kAll = [](const std::string&) { return true; };

MethodMetrics metricsOf(const Trajectory& run, const Trajectory& ref, const Trajectory& tight) {
  const ComparisonResult r = compareTrajectories(ref, tight, {run}, CompareOptions{});
  return r.metrics[0];
}

}  // namespace

TEST_CASE("a run written out and read back gives the run's own metrics", "[outside][recorded]") {
  for (const char* scene : {"pendulum5.json", "pendulum5_ball.json"}) {
    const Model m = test::loadData(scene);
    const Trajectory run = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 2e-3)));
    const Trajectory ref = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 1.0, 1e-12)));
    const Trajectory tight = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 1.0, 1e-14)));
    const Method rec = addRecordedRun(freshName(), csvWith(run, std::string("own-") + scene + ".csv", kAll), m);
    const Trajectory back = recordedTrajectory(m, checked(test::runSpec(rec, Integrator::RK4, 1.0, 1e-3)));
    const MethodMetrics a = metricsOf(run, ref, tight), b = metricsOf(back, ref, tight);
    INFO(scene);
    CHECK(b.pose.value == a.pose.value);  // 17 digits written: every q and u read back to the bit
    CHECK(b.coord.value == a.coord.value);
    CHECK(b.energy.value == a.energy.value);
    CHECK(b.divergence_time_s == a.divergence_time_s);
    CHECK(b.status() == Outcome::Ok);
    CHECK(recordedSource(rec)["grid"] == "every grid time is a sample");
    CHECK(recordedSource(rec)["speeds"] == "file");
  }
}

TEST_CASE("body poses alone give the run's pose errors, its coordinates and, by differences, its energy", "[outside][recorded]") {
  const Model m = test::loadData("pendulum5_ball.json");  // a ball joint: a quaternion read back from poses
  const Trajectory run = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 1e-3, 0.002)));
  const auto poses = [](const std::string& c) {
    return c == "t" || c.size() > 2 && (c.find(".x") != std::string::npos || c.find(".y") != std::string::npos ||
                                        c.find(".z") != std::string::npos || c.find(".q") != std::string::npos &&
                                        c.find(".q0") == std::string::npos && c.find(".q1") == std::string::npos &&
                                        c.find(".q2") == std::string::npos && c.find(".q3") == std::string::npos);
  };
  const Method rec = addRecordedRun(freshName(), csvWith(run, "poses.csv", poses), m);
  CHECK(recordedRun(rec)->format == "body-poses");
  CHECK(recordedRun(rec)->speeds == "five-point differences (fourth order in the spacing)");
  const Trajectory back = recordedTrajectory(m, checked(test::runSpec(rec, Integrator::RK4, 1.0, 1e-3, 0.01)));
  Trajectory own = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 1e-3, 0.01)));
  CHECK(test::maxPoseDiff(back, own) < 1e-14);
  // Coordinates: jointCoordinates inverts the kinematics to round-off.
  double dq = 0, dE = 0;
  for (size_t k = 0; k < own.size(); ++k) {
    for (const int i : own.angle_coords) dq = std::max(dq, std::abs(back.q[k][i] - own.q[k][i]));
    dE = std::max(dE, std::abs(back.energy[k] - own.energy[k]) / std::abs(own.energy[0]));
  }
  CHECK(dq < 1e-10);
  // Speeds by five-point differences at h = 2 ms: error ~h^4/30 |u^(5)|; the energy within 1e-3 of E(0).
  CHECK(dE < 1e-3);
  CHECK(recordedRun(rec)->max_joint_separation < 1e-12);  // the in-house poses hold their joints
}

TEST_CASE("a body-poses log every 10 ms gives the run's energy: five-point speeds, the spacing's effect stated", "[outside][recorded]") {
  // Issue 53 item 19: three-point differences over 10 ms inflated an ODE log's energy error (0.117 against its true
  // 0.0945). The three-point speeds err by h^2/6 |u(3)|, the five-point ones by h^4/30 |u(5)|: far less where the
  // motion is smooth on the spacing, less by ~10x at pendulum5's fastest whips.
  const Model m = test::loadData("pendulum5.json");
  const Trajectory run = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 2.0, 1e-3, 0.01)));
  const auto poses = [](const std::string& c) {
    return c == "t" || c.find(".x") != std::string::npos || c.find(".y") != std::string::npos || c.find(".z") != std::string::npos ||
           (c.find(".q") != std::string::npos && c.find(".q0") == std::string::npos && c.find(".q1") == std::string::npos &&
            c.find(".q2") == std::string::npos && c.find(".q3") == std::string::npos);
  };
  const Method rec = addRecordedRun(freshName(), csvWith(run, "poses10.csv", poses), m);
  const Trajectory back = recordedTrajectory(m, checked(test::runSpec(rec, Integrator::RK4, 2.0, 1e-3, 0.01)));
  double dE = 0, T = 0;
  for (size_t k = 0; k < run.size(); ++k) {
    dE = std::max(dE, std::abs(back.energy[k] - run.energy[k]));
    T = std::max(T, run.kinetic[k]);
  }
  const double effect = recordedSource(rec)["speeds_spacing_effect"].get<double>();
  INFO("energy difference " << dE / T << " of max T; three- against five-point " << effect);
  // Measured: the five-point speeds' kinetic energy within 2.9e-3 of max T at the fastest whip (t = 1.43 s), the
  // three-point speeds' 2.8e-2 (the stated effect). Held: the stated effect is at least 1e-3, and the five-point
  // speeds' error is within a fifth of it (three-point speeds, injected, give 0 for the effect and fail both).
  CHECK(effect > 1e-3);
  CHECK(dE / T < 0.2 * effect);
  CHECK(back.run.dt == 0.01);   // the median spacing as written, not 0.009999999999999787
}

TEST_CASE("samples off the grid are interpolated and said to be, and a file that ends early is a failure there", "[outside][recorded]") {
  const Model m = test::loadData("pendulum5.json");
  const Trajectory run = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 1e-3, 0.004)));
  const Method rec = addRecordedRun(freshName(), csvWith(run, "coarse.csv", kAll), m);
  const Trajectory back = recordedTrajectory(m, checked(test::runSpec(rec, Integrator::RK4, 1.0, 1e-3, 0.01)));
  const Trajectory own = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 1e-3, 0.01)));
  CHECK(recordedSource(rec)["grid"].get<std::string>().rfind("linear between samples", 0) == 0);
  // Linear interpolation at spacing h = 4 ms errs by at most h^2/8 max|q''| (u = q' here: no quaternion);
  // max|q''| from the file's own speeds, its estimate's error covered by a factor 1.5.
  double qdd = 0;
  for (size_t k = 1; k < run.size(); ++k) qdd = std::max(qdd, (run.u[k] - run.u[k - 1]).cwiseAbs().maxCoeff() / 0.004);
  double dq = 0;
  for (size_t k = 0; k < own.size(); ++k) dq = std::max(dq, (back.q[k] - own.q[k]).cwiseAbs().maxCoeff());
  CHECK(dq <= 1.5 * 0.004 * 0.004 / 8 * qdd);
  CHECK(dq > 0);

  const Method early = addRecordedRun(freshName(), csvWith(run, "early.csv", kAll, 1, 0.5), m);
  const Trajectory cut = recordedTrajectory(m, checked(test::runSpec(early, Integrator::RK4, 1.0, 1e-3, 0.01)));
  CHECK(cut.failure_kind == Failure::EndedEarly);
  CHECK(cut.failure_time == Approx(0.5));
  CHECK(cut.t.back() == Approx(0.5));
}

TEST_CASE("what the file declares is kept, its CPU time is the run's", "[outside][recorded]") {
  const Model m = test::loadData("pendulum5.json");
  const Trajectory run = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 0.1, 1e-3)));
  const std::string body = [&] {
    std::ifstream in(csvWith(run, "plain.csv", kAll));
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }();
  const Method rec = addRecordedRun(freshName(), writeText("declared.csv", "# simulator: a script\n# cpu_s: 0.25\n#\n" + body), m);
  const Trajectory back = recordedTrajectory(m, checked(test::runSpec(rec, Integrator::RK4, 0.1, 1e-3)));
  CHECK(back.run_time_s == 0.25);
  CHECK(recordedSource(rec)["declared"]["simulator"] == "a script");
  CHECK(recordedSource(rec)["sha256"].get<std::string>().size() == 64);
  CHECK(integratorName(back.run.integrator) == std::string("recorded"));
}

TEST_CASE("a recorded run saved with a UTF-8 byte-order mark reads as the same run", "[outside][recorded]") {
  // Issue 53 item 16: the mark made "must be 't' (got 't')"; spreadsheets write it.
  const Model m = test::loadData("pendulum5.json");
  const Trajectory run = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 0.1, 1e-3)));
  std::ifstream in(csvWith(run, "marked.csv", kAll));
  std::ostringstream body;
  body << in.rdbuf();
  const Method plain = addRecordedRun(freshName(), writeText("plain-bom.csv", body.str()), m);
  const Method marked = addRecordedRun(freshName(), writeText("bom.csv", "\xEF\xBB\xBF" + body.str()), m);
  CHECK(recordedRun(marked)->q == recordedRun(plain)->q);
  CHECK(recordedRun(marked)->t == recordedRun(plain)->t);
}

TEST_CASE("malformed recorded runs: one line naming the file, the line and the column", "[outside][recorded]") {
  const Model m = test::loadData("pendulum5.json");  // a gimbal root link1 (q0..q2), then revolute link2..link5
  const std::string q = "link1.q0,link1.q1,link1.q2,link2.q0,link3.q0,link4.q0,link5.q0";
  Eigen::VectorXd qf;
  m.qToFile(m.q0(), qf);
  std::string start;
  for (int i = 0; i < qf.size(); ++i) start += "," + gnum(qf[i], 17);
  const auto row = [](const std::string& t, const std::string& first) { return t + "," + first + ",0,0,0,0,0,0\n"; };
  struct Case {
    const char* what;
    std::string text, message;
  };
  const std::vector<Case> cases = {
      {"empty", "", "empty"},
      {"only comments", "# cpu_s: 1\n", "no header line"},
      {"first column not t", "time," + q + "\n", "line 1: the header's first column must be 't' (got 'time')"},
      {"a column twice", "t," + q + ",link1.q0\n", "line 1, column 9 ('link1.q0'): named twice (also column 2)"},
      {"a foreign scene's body", "t," + q + ",arm.x\n", "line 1, column 9 ('arm.x'): scene 'pendulum5' has no body or joint 'arm'"},
      {"an unknown column", "t," + q + ",speed\n", "line 1, column 9 ('speed'): not a column"},
      {"an empty column name", "t,," + q + "\n", "line 1, column 2 (''): an empty column name"},
      {"a missing coordinate", "t,link1.q0,link2.q0\n0,0,0\n", "line 1: column 'link1.q1' is missing"},
      {"half the speeds", "t," + q + ",link1.u0\n", "line 1: column 'link1.u1' is missing (the speeds are all given or none)"},
      {"neither format", "t,energy\n0,1\n", "line 1: neither format"},
      {"half a pose", "t,link1.x,link1.y\n", "line 1: column 'link1.z' is missing (body-pose format"},
      {"a short row", "t," + q + "\n0" + start + "\n0.01,1,2\n", "line 3: 3 fields, the header has 8"},
      {"an empty field", "t," + q + "\n0" + start + "\n" + row("0.01", ""), "line 3, column 2 ('link1.q0'): empty"},
      {"not a number", "t," + q + "\n0" + start + "\n" + row("0.01", "abc"), "line 3, column 2 ('link1.q0'): not a number: 'abc'"},
      {"not finite", "t," + q + "\n0" + start + "\n" + row("0.01", "nan"), "line 3, column 2 ('link1.q0'): not finite: 'nan'"},
      {"time standing still", "t," + q + "\n0" + start + "\n0" + start + "\n", "line 3, column 1 ('t'): time 0 does not increase (line 2 has 0)"},
      {"time going back", "t," + q + "\n0" + start + "\n0.02" + start + "\n0.01" + start + "\n", "line 4, column 1 ('t'): time 0.01 does not increase"},
      {"a late start", "t," + q + "\n0.5" + start + "\n", "line 2, column 1 ('t'): the first sample is at t = 0.5; the scene starts at 0"},
      {"one sample", "t," + q + "\n0" + start + "\n", "fewer than two samples"},
      {"another initial state", "t," + q + "\n" + row("0", "1") + row("0.01", "1"), "line 2: the first sample is not the scene's initial state: 'link1.q0' is 1"},
      {"a bad cpu_s", "# cpu_s: fast\nt," + q + "\n", "line 1: cpu_s: a CPU time in seconds >= 0, got 'fast'"},
      // Issue 53 items 16 and 20: bytes from outside escaped, hexadecimal floats and a key said twice refused.
      {"ESC in a field", "t," + q + "\n0" + start + "\n" + row("0.01", "1\x1b[2J"), "line 3, column 2 ('link1.q0'): not a number: '1\\x1b[2J'"},
      {"ESC in a column name", "t," + q + ",a\x1b.x\n", "column 9 ('a\\x1b.x'): scene 'pendulum5' has no body or joint 'a\\x1b'"},
      {"a hexadecimal float", "t," + q + "\n0" + start + "\n" + row("0.01", "0x1p-3"),
       "line 3, column 2 ('link1.q0'): a hexadecimal number '0x1p-3': decimal numbers only"},
      {"cpu_s twice", "# cpu_s: 1\n# cpu_s: 2\nt," + q + "\n", "line 2: 'cpu_s' declared twice"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    const std::string path = writeText("bad.csv", c.text);
    CHECK_THROWS_WITH(addRecordedRun(freshName(), path, m), Catch::StartsWith(path + ": ") && Catch::Contains(c.message));
  }
  CHECK_THROWS_WITH(addRecordedRun(freshName(), "/nonexistent.csv", m), "/nonexistent.csv: cannot open the recorded run");
  // Bounded (io/csv.hpp): a device has no end, so it is refused before any byte is read; a
  // folder likewise. The device is made in the test's own folder, never /dev's.
  const std::string zero = tempDir() + "/zero";
  std::remove(zero.c_str());
  REQUIRE(::mknod(zero.c_str(), S_IFCHR | 0600, ::makedev(1, 5)) == 0);
  CHECK_THROWS_WITH(addRecordedRun(freshName(), zero, m), zero + ": not a regular file (a device or a pipe has no bound): not a recorded run");
  std::remove(zero.c_str());
  CHECK_THROWS_WITH(addRecordedRun(freshName(), tempDir(), m), tempDir() + ": is a folder, not a recorded run");
  CHECK_THROWS_WITH(addRecordedRun("eigen", writeText("x.csv", "t\n"), m), "run name 'eigen': a method of that name exists");
  // A unit quaternion is checked where the format has one.
  const Model ball = test::loadData("pendulum5_ball.json");
  const Trajectory run = simulate(ball, checked(test::runSpec(Method::Classical, Integrator::RK4, 0.02, 1e-3)));
  std::string text;
  {
    std::ifstream in(csvWith(run, "ball.csv", kAll));
    std::ostringstream s;
    s << in.rdbuf();
    text = s.str();
  }
  const size_t row2 = text.find('\n', text.find('\n') + 1) + 1;  // the second sample's line (line 3)
  const size_t field = text.find(',', text.find(',', row2) + 1) + 1;  // its third field
  text.replace(field, text.find(',', field) - field, "0.5");
  const std::string path = writeText("ballbad.csv", text);
  CHECK_THROWS_WITH(addRecordedRun(freshName(), path, ball), Catch::Contains("line 3, column") && Catch::Contains("the quaternion's norm is"));
}

// Issue 73, item 12: recorded runs were refused on every mechanism ("its u' comes from outside the
// formation"), though a recorded run has no u'. The oracle is the in-house run written out and read back.
TEST_CASE("a recorded run of a mechanism is judged by its samples, its loops measured by our g(q)", "[outside][recorded][mechanism]") {
  const Model m = test::loadData("mechanisms/andrews.json");
  const Trajectory run = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 0.03, 1e-10, 1e-3)));
  const Trajectory ref = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 0.03, 1e-12, 1e-3)));
  const Trajectory tight = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 0.03, 1e-13, 1e-3)));
  REQUIRE_NOTHROW(requireMethodTakes(addRecordedRun(freshName(), csvWith(run, "andrews-own.csv", kAll), m), m));
  const Method rec = addRecordedRun(freshName(), csvWith(run, "andrews-own2.csv", kAll), m);
  const Trajectory back = recordedTrajectory(m, checked(test::runSpec(rec, Integrator::RK4, 0.03, 1e-3, 1e-3)));
  REQUIRE(back.has_loops);
  CHECK(back.loops.position_m < 1e-12);  // the run kept them to round-off (the projection's 1e-12 tolerance)
  const MethodMetrics a = metricsOf(run, ref, tight), b = metricsOf(back, ref, tight);
  CHECK(b.pose.value == a.pose.value);
  CHECK(std::abs(b.energy.value - a.energy.value) <= 1e-12 * std::max(1.0, a.energy.value));  // its dissipated column read
  CHECK(recordedSource(rec)["dissipated"] == "the file's dissipated column");
  // A file whose loops are open by 1e-3 rad in one crank angle: our g(q) sees it.
  std::ifstream in(csvWith(run, "andrews-edit.csv", kAll));
  std::ostringstream edited;
  std::string line;
  std::getline(in, line);
  edited << line << '\n';
  for (int k = 0; std::getline(in, line); ++k) {
    if (k > 0) {  // the start stays as written (a recorded run must start where the scene does)
      const size_t a0 = line.find(','), a1 = line.find(',', a0 + 1);
      const double q = std::stod(line.substr(a0 + 1, a1 - a0 - 1)) + 1e-3;
      char buf[40];
      std::snprintf(buf, sizeof buf, "%.17g", q);
      line = line.substr(0, a0 + 1) + buf + line.substr(a1);
    }
    edited << line << '\n';
  }
  const Method bent = addRecordedRun(freshName(), writeText("andrews-bent.csv", edited.str()), m);
  const Trajectory bent_back = recordedTrajectory(m, checked(test::runSpec(bent, Integrator::RK4, 0.03, 1e-3, 1e-3)));
  CHECK(bent_back.loops.position_m > 1e-5);  // a crank 1e-3 rad off opens its loop by ~1e-3 x its length
}

TEST_CASE("a recorded run of a scene with point spring-dampers: W_diss from its column, else the samples' power, said which", "[outside][recorded][mechanism]") {
  const Model m = test::loadData("mechanisms/iftomm_a05.json");  // a tree with stiff point spring-dampers
  const Trajectory run = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 1.0, 1e-10, 1e-2)));
  const Trajectory ref = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 1.0, 1e-12, 1e-2)));
  const Trajectory tight = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, 1.0, 1e-13, 1e-2)));
  const MethodMetrics a = metricsOf(run, ref, tight);
  const Method with = addRecordedRun(freshName(), csvWith(run, "a05-own.csv", kAll), m);
  const Trajectory back = recordedTrajectory(m, checked(test::runSpec(with, Integrator::RK4, 1.0, 1e-3, 1e-2)));
  CHECK(std::abs(metricsOf(back, ref, tight).energy.value - a.energy.value) <= 1e-12 * std::max(1.0, a.energy.value));
  const Method without = addRecordedRun(freshName(), csvWith(run, "a05-nodiss.csv", [](const std::string& c) { return c != "dissipated"; }), m);
  CHECK(recordedSource(without)["dissipated"].get<std::string>().find("trapezoid rule over the samples' non-conservative power") != std::string::npos);
  const Trajectory quad = recordedTrajectory(m, checked(test::runSpec(without, Integrator::RK4, 1.0, 1e-3, 1e-2)));
  // The quadrature over 10-ms samples of a power that varies on the springs' time scale is not exact:
  // its figure differs from the exact run's, and only by the rule's error (below 1e-2 of E_scale here).
  const double e_quad = metricsOf(quad, ref, tight).energy.value;
  WARN("energy figure: exact run " << a.energy.value << ", its samples by the trapezoid rule " << e_quad);
  CHECK(e_quad > 10 * a.energy.value);
  CHECK(e_quad < 1e-2);
}
