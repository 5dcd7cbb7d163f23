// outside/plugin.cpp: a plugin's u' as a method. The oracle is the in-house
// classical method (and so, through its own tests, Simbody and MuJoCo): the
// example plugin (examples/plugin/rnea_plugin.c, its own Newton-Euler code)
// must agree with it; the hostile plugins must each end in one line.
#include <catch2/catch.hpp>

#include "compare/crosscheck.hpp"
#include "compare/engines.hpp"
#include "outside/plugin.hpp"
#include "solver/formation.hpp"
#include "solver/integrate.hpp"
#include "solver/mechanism/formulation.hpp"
#include "solver/mechanism/projection.hpp"
#include "support.hpp"

using namespace em;

namespace {

std::string lib(const std::string& name) { return std::string(EM_BINARY_DIR) + "/lib/lib" + name + ".so"; }

Method plugin(const std::string& name) { return addPlugin(name, lib(name)); }

// The in-house u' at (q, u) (classical: A's Cholesky), internal order.
Eigen::VectorXd classicalUdot(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u, Eigen::MatrixXd& A) {
  Workspace ws(m);
  formEquations(m, q.data(), u.data(), ws);
  A = ws.A;
  return ws.A.llt().solve(ws.B);
}

}  // namespace

TEST_CASE("the example plugin's u' equals classical's within 4 eps cond(A) at random states", "[outside][plugin]") {
  const Method rnea = plugin("rnea");
  // Shipped revolute scenes, and random revolute trees (turned full inertias, springs and dampers) no one tuned on.
  std::vector<Model> models = {test::loadData("pendulum5.json"), test::loadData("chain20.json"), test::loadData("chain50.json")};
  for (unsigned seed : {11u, 12u, 13u}) models.push_back(test::randomTree(seed, 8, false, true));
  for (const Model& m : models) {
    std::mt19937 rng(7);
    std::vector<Eigen::VectorXd> qs, us;
    for (int k = 0; k < 20; ++k) {
      Eigen::VectorXd q, u;
      randomState(m, rng, q, u);
      qs.push_back(q);
      us.push_back(u);
    }
    const std::vector<Eigen::VectorXd> got = pluginUdots(rnea, m, qs, us);
    REQUIRE(got.size() == qs.size());
    for (size_t k = 0; k < qs.size(); ++k) {
      Eigen::MatrixXd A;
      const Eigen::VectorXd want = classicalUdot(m, qs[k], us[k], A);
      INFO(m.name << " state " << k);
      CHECK(test::relErr(got[k], want, 1.0) <= test::udotTolerance(A));
    }
  }
}

TEST_CASE("the example plugin's trajectory equals classical's under the same integrator", "[outside][plugin]") {
  const Method rnea = plugin("rnea");
  const Model m = test::loadData("pendulum5.json");
  for (Integrator integ : {Integrator::RK4, Integrator::RKF45}) {
    const RunSpec s = test::runSpec(rnea, integ, 1.0, integ == Integrator::RK4 ? 1e-3 : 1e-9);
    RunSpec c = s;
    c.method = Method::Classical;
    const Trajectory a = runTrajectory(m, checked(s)), b = simulate(m, checked(c));
    REQUIRE_FALSE(a.failed());
    REQUIRE(a.size() == b.size());
    // u' agrees to ~1e-14; over 1 s of a chaotic pendulum (exponent ~1.7 /s) the
    // difference grows by e^1.7 at most: 1e-11 is a thousand times that.
    CHECK(test::stateDiff(a, b, 1.0) < 1e-11);
    CHECK(a.rhs_evals == b.rhs_evals);  // the same steps, taken in a child process
  }
}

TEST_CASE("a plugin's run in a child process is the run in-process, bit for bit", "[outside][plugin]") {
  const Method ok = plugin("hostile_ok");
  const Model m = test::loadData("pendulum5.json");
  const RunSpec s = test::runSpec(ok, Integrator::RK4, 0.5, 1e-3);
  const Trajectory isolated = runTrajectory(m, checked(s)), direct = simulate(m, checked(s));
  REQUIRE(isolated.size() == direct.size());
  for (size_t k = 0; k < direct.size(); ++k) {
    CHECK(isolated.q[k] == direct.q[k]);
    CHECK(isolated.u[k] == direct.u[k]);
    CHECK(isolated.energy[k] == direct.energy[k]);
  }
  CHECK(pluginSource(ok)["sha256"].get<std::string>().size() == 64);
  CHECK(pluginSource(Method::Classical).is_null());
}

TEST_CASE("a bad library is refused in one line naming the file", "[outside][plugin]") {
  CHECK_THROWS_WITH(plugin("hostile_abi"), Catch::Contains("libhostile_abi.so: built against plugin ABI 101, this eigenmass speaks 3"));
  CHECK_THROWS_WITH(plugin("hostile_nosym"), Catch::Contains("libhostile_nosym.so: no symbol em_plugin_udot"));
  CHECK_THROWS_WITH(addPlugin("text", test::sourcePath("README.md")), Catch::Contains("README.md: not a loadable library"));
  CHECK_THROWS_WITH(addPlugin("gone", "/nonexistent/libx.so"), "/nonexistent/libx.so: cannot read the plugin");
  CHECK_THROWS_WITH(addPlugin("classical", lib("rnea")), "plugin name 'classical': a method of that name exists");
  CHECK_THROWS_WITH(addPlugin("a b", lib("rnea")), Catch::Contains("plugin name 'a b': letters, digits"));
}

TEST_CASE("a plugin that fails at the initial state is refused before any run, in one line", "[outside][plugin]") {
  const Model m = test::loadData("pendulum5.json");
  const double timeout = pluginTimeout();
  setPluginTimeout(0.5);
  CHECK_THROWS_WITH(probePlugin(plugin("hostile_nan"), m), Catch::Contains("libhostile_nan.so: u' at the initial state is not finite"));
  CHECK_THROWS_WITH(probePlugin(plugin("hostile_segv"), m),
                    Catch::Contains("libhostile_segv.so: crashed (SIGSEGV) in em_plugin_udot at t = 0, at the initial state of pendulum5"));
  CHECK_THROWS_WITH(probePlugin(plugin("hostile_hang"), m),
                    Catch::Contains("libhostile_hang.so: no return within 0.5 s (killed) in em_plugin_udot at t = 0") &&
                        Catch::Contains("(--plugin-timeout)"));
  CHECK_THROWS_WITH(probePlugin(plugin("hostile_null"), m),
                    Catch::Contains("em_plugin_create returned NULL: this plugin refuses\\nevery \\x1b[31mmodel"));
  CHECK_THROWS_WITH(probePlugin(plugin("hostile_error"), m),
                    Catch::Contains("em_plugin_udot returned an error at the initial state: plugin 'hostile_error': the plugin gave up at t = 0"));
  CHECK_THROWS_WITH(probePlugin(plugin("rnea"), test::loadData("pendulum5_ball.json")),
                    Catch::Contains("revolute, universal and gimbal joints only (body"));
  setPluginTimeout(timeout);
}

// A plugin written from the header alone names every joint kind it is handed:
// the planar sled's joints reach it as EM_PLANAR and EM_REVOLUTE, never as an
// unnamed value (ABI 2 passed a planar joint as 6, which its header did not name).
TEST_CASE("a plugin written from the header names every joint kind it receives, planar included", "[outside][plugin]") {
  const Model m = test::loadData("planar_sled.json");
  std::string kinds;
  for (const Body& b : m.bodies) kinds += std::string(" ") + jointTypeName(b.joint.type);
  CHECK_THAT(kinds, Catch::Contains("planar"));
  CHECK_THROWS_WITH(probePlugin(plugin("hostile_kinds"), m), Catch::Contains("em_plugin_create returned NULL: kinds:" + kinds));
}

// ida and the trapezoidal rule integrate the formation's A and B themselves:
// a plugin's u' under them was never called, and the run was classical's under
// the plugin's name (judged "ok" with classical's error). Refused before any run.
TEST_CASE("a plugin's u' is never replaced by the formation's: ida and the trapezoidal rule refuse it", "[outside][plugin]") {
  const Method ok = plugin("hostile_ok");
  for (const char* scene : {"pendulum5.json", "mechanisms/iftomm_a02_n2.json"}) {
    const Model m = test::loadData(scene);
    for (Integrator i : {Integrator::IDA, Integrator::Trapezoidal}) {
      INFO(scene << " " << info(i).name);
      RunSpec s = test::runSpec(ok, i, 0.5, i == Integrator::IDA ? 1e-8 : 1e-3);
      if (i == Integrator::Trapezoidal) s.options.loops.formulation = Formulation::AugmentedLagrangian;
      CHECK_THROWS_WITH(refuseUnrunnable(m, s), Catch::Contains("method hostile_ok's u' comes from outside the formation"));
    }
  }
  for (Method builtin : {Method::Classical, Method::Articulated}) CHECK_NOTHROW(refuseUnrunnable(test::loadData("pendulum5.json"),
                                                                                                  test::runSpec(builtin, Integrator::IDA, 0.5, 1e-8)));
}

TEST_CASE("a plugin that fails during a run ends that run with its time and cause, its samples before kept", "[outside][plugin]") {
  const Model m = test::loadData("pendulum5.json");
  const double timeout = pluginTimeout();
  setPluginTimeout(0.5);
  struct Case {
    const char* name;
    const char* cause;
  };
  for (const Case& c : {Case{"hostile_late_segv", "crashed (SIGSEGV) in em_plugin_udot at t = 0.25"},
                        Case{"hostile_late_hang", "no return within 0.5 s (killed) in em_plugin_udot at t = 0.25"},
                        Case{"hostile_late_error", "the plugin gave up at t = 0.25"}}) {
    const Trajectory tr = runTrajectory(m, checked(test::runSpec(plugin(c.name), Integrator::RK4, 1.0, 1e-3)));
    INFO(c.name << ": " << tr.failure);
    CHECK(tr.failure_kind == Failure::Plugin);
    CHECK_THAT(tr.failure, Catch::Contains(c.cause));
    CHECK(tr.failure_time == Approx(0.25).margin(1e-3));
    CHECK(tr.t.back() == Approx(0.24).margin(1e-3));  // the samples before it: 25 of them
  }
  setPluginTimeout(timeout);
}

TEST_CASE("on a mechanism the example plugin's constrained u' equals the in-house one at 20 consistent states", "[outside][plugin][mechanism]") {
  // The oracle: the in-house tree (A, B with the drives and point springs)
  // and its multipliers by Cholesky (constrainedAt, eq. (M7)); the plugin's
  // u' is its own Newton-Euler code, tau from eigenmass, A^-1 G^T from the
  // plugin by differences in tau. Andrews has a drive, a point spring and
  // three ball loops (9 rows, rank 6); A04 (Bricard) a redundant hinge loop;
  // A02 (N = 2) two balls on a planar chain.
  const Method rnea = plugin("rnea");
  for (const char* scene : {"mechanisms/andrews.json", "mechanisms/iftomm_a04.json", "mechanisms/iftomm_a02_n2.json"}) {
    const Model m = test::loadData(scene);
    std::mt19937 rng(3);
    std::vector<Eigen::VectorXd> qs, us;
    while (qs.size() < 20) {  // consistent states, as crosscheck draws them
      Eigen::VectorXd q, u;
      consistentState(m, rng, q, u);
      qs.push_back(q), us.push_back(u);
    }
    const std::vector<Eigen::VectorXd> got = pluginUdots(rnea, m, qs, us);
    REQUIRE(got.size() == qs.size());
    for (size_t k = 0; k < qs.size(); ++k) {
      Workspace ws(m);
      formEquations(m, qs[k].data(), us[k].data(), ws);
      const ConstrainedEquations want = constrainedAt(m, ws, us[k].data());
      const double scale = std::max(want.udot.cwiseAbs().maxCoeff(), ws.A.llt().solve(ws.B).cwiseAbs().maxCoeff());
      INFO(scene << " state " << k);
      // Both are backward-stable solves of the same equations: round-off
      // times cond(A) (udotTolerance) times the closures' conditioning,
      // which Simbody's constrained u' meets at 1.6e-12 on Andrews; 1e3 x
      // cond(A) eps leaves room for the differences in tau (2 eps of u' each).
      CHECK((got[k] - want.udot).cwiseAbs().maxCoeff() / scale <= 1e3 * test::udotTolerance(ws.A));
    }
  }
}

TEST_CASE("the example plugin on Andrews' squeezer meets the published solution: its loops closed around it, its drive and spring through tau", "[outside][plugin][mechanism]") {
  // The IVP test set's SOLN at t = 0.03 s (PSIDE at rtol = atol = 1e-14;
  // tests/solver/test_mechanism.cpp holds the in-house routes to it), and
  // the bar, 1e-9 relative, for each of the seven angles.
  const double published[7] = {15.81077119629904,  -15.75637105984298, 0.04082224013073101, -0.5347301163226948,
                               0.5244099658805304, 0.5347301163226948, 1.048080741042263};
  const Method rnea = plugin("rnea");
  const Model m = test::loadData("mechanisms/andrews.json");
  for (const Formulation f : {Formulation::Projection, Formulation::UdwadiaKalaba}) {
    RunSpec s = test::runSpec(rnea, Integrator::RK8PD, 0.03, 1e-13, 0.03);
    s.options.loops.formulation = f;
    const Trajectory tr = runTrajectory(m, checked(s));
    INFO(formulationName(f));
    REQUIRE_FALSE(tr.failed());
    for (int k = 0; k < 7; ++k) {
      INFO("angle " << k << ": " << tr.q.back()[k] << " against " << published[k]);
      CHECK(std::abs(tr.q.back()[k] - published[k]) <= 1e-9 * std::abs(published[k]));
    }
    // E + W_diss (the drive's work negative) conserved as in-house (tests/solver/test_mechanism.cpp: 1e-8 J).
    for (size_t j = 0; j < tr.size(); ++j) CHECK(std::abs(tr.energy[j] + tr.dissipated[j] - tr.energy[0]) < 1e-8);
  }
}

TEST_CASE("a plugin that fails in the multipliers' extra calls ends the run with its own message", "[outside][plugin][mechanism]") {
  // hostile_late_tau refuses a nonzero tau from t = 0.25 s on. On A04 (no
  // drive, no point spring) tau is zero but in the calls that take A^-1 G^T:
  // the run must fail there with the plugin's words, not "A not positive definite".
  const Method late = plugin("hostile_late_tau");
  const Model m = test::loadData("mechanisms/iftomm_a04.json");
  for (const Formulation f : {Formulation::Projection, Formulation::UdwadiaKalaba}) {
    RunSpec s = test::runSpec(late, Integrator::RK4, 0.5, 1e-3);
    s.options.loops.formulation = f;
    const Trajectory tr = runTrajectory(m, checked(s));
    INFO(formulationName(f));
    REQUIRE(tr.failed());
    CHECK(tr.failure_kind == Failure::Plugin);
    CHECK_THAT(tr.failure, Catch::Contains("plugin 'hostile_late_tau': no tau wanted (t = 0.25)"));
  }
}
