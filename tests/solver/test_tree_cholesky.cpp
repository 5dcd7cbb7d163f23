// A's tree-sparse factors (docs/theory.md §16) against the dense Cholesky they
// replace: the solves, the mechanism's multipliers and projections, G's
// pattern; and a row of four-bars of other lengths and masses against its
// parallel branch, a one-degree-of-freedom pendulum.
#include <cmath>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "solver/formation.hpp"
#include "solver/integrate.hpp"
#include "solver/mechanism/constrained.hpp"
#include "solver/tree_cholesky.hpp"
#include "support.hpp"

using namespace em;

namespace {

// The tree-sparse path sums in another order than the dense one: the two agree
// to round-off amplified by cond(A) and cond(G A^-1 G^T) (below 1e6 on these
// scenes at these states): 1e-9 relative to the largest entry.
constexpr double kRoundOff = 1e-9;

double relGap(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

// The shipped mechanisms and the tests' own: every closure kind, sliding and spherical joints.
const char* const kMechanisms[] = {"data/scenes/mechanisms/andrews.json",
                                   "data/scenes/mechanisms/iftomm_a02_n2.json", "data/scenes/mechanisms/iftomm_a02_n40.json",
                                   "data/scenes/mechanisms/iftomm_a04.json",
                                   "tests/scenes/mechanisms/rsur_universal.json", "tests/scenes/mechanisms/slider_crank_closed.json",
                                   "tests/scenes/mechanisms/bead_on_rail.json"};

// A row of n parallelogram four-bars: n + 1 cranks (length lc, mass mc,
// uniform rods) on the ground at spacing s, vertical; n couplers (length s,
// mass mk) from each crank's tip to the next one's, closed by a ball; B0 moving at v0 along x.
std::string fourBarRow(int n, double lc, double s, double mc, double mk, double v0) {
  std::ostringstream o;
  o.precision(17);
  const auto rod = [&](double mass, double len) {
    o << "\"mass\": " << mass << ", \"inertia\": [1e-6, " << mass * len * len / 12 << ", " << mass * len * len / 12 << "], ";
  };
  o << R"({"format": "eigenmass-scene/1", "name": "row", "gravity": [0, -9.81, 0], "bodies": [)";
  for (int i = 0; i <= n; ++i) {
    o << (i ? ", " : "") << "{\"name\": \"crank" << i << "\", \"parent\": \"ground\", ";
    rod(mc, lc);
    o << R"("joint": {"type": "revolute", "axis": [0, 0, 1], "in_parent": [)" << i * s << ", 0, 0], \"in_body\": [" << -lc / 2
      << ", 0, 0], \"q0\": [" << M_PI / 2 << "], \"u0\": [" << -v0 / lc << "]}}";
  }
  for (int i = 1; i <= n; ++i) {
    o << ", {\"name\": \"coupler" << i << "\", \"parent\": \"crank" << i - 1 << "\", ";
    rod(mk, s);
    o << R"("joint": {"type": "revolute", "axis": [0, 0, 1], "in_parent": [)" << lc / 2 << ", 0, 0], \"in_body\": [" << -s / 2
      << ", 0, 0], \"q0\": [" << -M_PI / 2 << "], \"u0\": [" << v0 / lc << "]}}";
  }
  o << "], \"loops\": [";
  for (int i = 1; i <= n; ++i)
    o << (i > 1 ? ", " : "") << "{\"name\": \"B" << i << "\", \"type\": \"ball\", \"body_a\": \"coupler" << i
      << "\", \"point_a\": [" << s / 2 << ", 0, 0], \"body_b\": \"crank" << i << "\", \"point_b\": [" << lc / 2 << ", 0, 0]}";
  o << R"(], "simulate": {"t_end": 1, "output_dt": 0.1}})";
  return o.str();
}

// The row's parallel branch: every crank turns by psi, every coupler
// translates with the tips, so M psi'' = -b cos psi with
// M = (n+1) mc lc^2 / 3 + n mk lc^2 and b = g lc ((n+1) mc / 2 + n mk);
// integrated by GSL's rk8pd at 1e-13. Returns psi at t.
struct Branch {
  double M, b;
};
int branchRates(double, const double y[], double f[], void* v) {
  const Branch& p = *static_cast<const Branch*>(v);
  f[0] = y[1];
  f[1] = -p.b / p.M * std::cos(y[0]);
  return GSL_SUCCESS;
}
double parallelBranch(int n, double lc, double mc, double mk, double v0, double t) {
  Branch p{(n + 1) * mc * lc * lc / 3 + n * mk * lc * lc, 9.81 * lc * ((n + 1) * mc / 2 + n * mk)};
  gsl_odeiv2_system sys{branchRates, nullptr, 2, &p};
  gsl_odeiv2_driver* d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-4, 1e-13, 1e-13);
  double y[2] = {M_PI / 2, -v0 / lc}, t0 = 0;
  const int status = gsl_odeiv2_driver_apply(d, &t0, t, y);
  gsl_odeiv2_driver_free(d);
  REQUIRE(status == GSL_SUCCESS);
  return y[0];
}

}  // namespace

TEST_CASE("the tree-sparse factors solve A x = B as the dense Cholesky does, and pay only on a wide tree", "[formation]") {
  std::mt19937 rng(11);
  for (const char* scene : {"data/scenes/forest.json", "data/scenes/tree_mixed.json", "data/scenes/pendulum5.json",
                            "data/scenes/solo12_tumbling.json", "data/scenes/mechanisms/iftomm_a05.json",
                            "data/scenes/mechanisms/iftomm_a02_n40.json"}) {
    const Model m = loadScene(test::sourcePath(scene)).model;
    TreeCholesky tree(m);
    Workspace ws(m);
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd q, u;
      randomState(m, rng, q, u);
      formEquations(m, q.data(), u.data(), ws);
      REQUIRE(tree.factor(ws.A));
      Eigen::VectorXd x = ws.B;
      tree.solveInPlace(x.data());
      INFO(scene << " trial " << trial);
      CHECK(relGap(x, ws.A.llt().solve(ws.B)) < kRoundOff);
      CHECK((ws.A * x - ws.B).cwiseAbs().maxCoeff() < kRoundOff * std::max(1.0, ws.B.cwiseAbs().maxCoeff()));
    }
  }
  // A chain fills its whole triangle: nothing to gain. A row of four-bars is two deep.
  CHECK_FALSE(TreeCholesky::pays(test::loadData("chain20.json")));
  CHECK_FALSE(TreeCholesky::pays(test::loadData("pendulum5.json")));
  CHECK(TreeCholesky::pays(test::loadData("mechanisms/iftomm_a02_n40.json")));
  const Model a02 = test::loadData("mechanisms/iftomm_a02_n40.json");
  const std::vector<int> parent = speedParents(a02);
  int roots = 0;
  for (int p : parent) roots += p < 0;
  CHECK(roots == 41);  // the cranks; each coupler's speed hangs from its crank's
}

TEST_CASE("a mechanism's multipliers and projections by the tree-sparse factors equal the dense ones", "[mechanism]") {
  std::mt19937 rng(5);
  for (const char* scene : kMechanisms) {
    const Model m = loadScene(test::sourcePath(scene)).model;
    const Eigen::VectorXd q = m.q0();
    Workspace ws(m);
    TreeCholesky tree(m);
    ConstrainedSolve dense(m), sparse(m);
    LoopState ls(m);
    for (int trial = 0; trial < 3; ++trial) {
      // The closed start at random speeds along the loops (G u = 0: on
      // redundant rows, Bricard's, the right-hand side is then consistent, as
      // along a run; off it the least-norm and the dropped-row solutions differ).
      Eigen::VectorXd qr, u;
      randomState(m, rng, qr, u);
      formEquations(m, q.data(), u.data(), ws);
      formLoops(m, ws, u.data(), ls);
      const Eigen::LLT<Eigen::MatrixXd> llt(ws.A);
      Eigen::MatrixXd AinvGt = llt.solve(ls.G.transpose());
      Eigen::VectorXd du(m.nu);
      dense.correction(ls, AinvGt, ls.Gu, du);
      u -= du;
      formEquations(m, q.data(), u.data(), ws);
      formLoops(m, ws, u.data(), ls);
      REQUIRE(tree.factor(ws.A));
      AinvGt = llt.solve(ls.G.transpose());
      Eigen::VectorXd gu = ls.Gu;
      ls.Gu = ls.G * (u + 0.1 * Eigen::VectorXd::Ones(m.nu));  // the correction's right-hand side: some G v, consistent
      Eigen::VectorXd a_dense = llt.solve(ws.B), a_sparse = a_dense;
      const int rank_dense = dense.solve(ls, AinvGt, 2.0, 3.0, a_dense);
      const int rank_sparse = sparse.solve(ls, tree, 2.0, 3.0, a_sparse);
      INFO(scene << " trial " << trial);
      CHECK(rank_sparse == rank_dense);
      CHECK(relGap(a_sparse, a_dense) < kRoundOff);
      // The closure forces G^T lambda agree (lambda itself may differ on redundant rows).
      CHECK(relGap(ls.G.transpose() * sparse.lambda(), ls.G.transpose() * dense.lambda()) < kRoundOff);
      Eigen::VectorXd dv_dense(m.nu), dv_sparse(m.nu);
      dense.correction(ls, AinvGt, ls.Gu, dv_dense);
      sparse.correction(ls, tree, ls.Gu, dv_sparse);
      CHECK(relGap(dv_sparse, dv_dense) < kRoundOff);
      CHECK((ls.Gu - ls.G * dv_sparse).cwiseAbs().maxCoeff() < kRoundOff * std::max(1.0, ls.Gu.cwiseAbs().maxCoeff()));
      ls.Gu = gu;
    }
  }
}

TEST_CASE("the augmented Lagrangian's penalized solves by the tree-sparse factors equal the dense ones (Woodbury)", "[mechanism]") {
  // eq. (S4): (A + G^T G / shift)^-1 G^T r / shift = A^-1 G^T (shift I + G A^-1 G^T)^-1 r,
  // the dense left side the oracle; and A + diag(extra) factored with its diagonal.
  // shift = 1e-6 of G A^-1 G^T's scale (the penalty ratio 1e6): cond grows by up
  // to 1e6, so the bound is looser than kRoundOff.
  constexpr double kPenaltyRoundOff = 1e-7;
  std::mt19937 rng(9);
  for (const char* scene : kMechanisms) {
    const Model m = loadScene(test::sourcePath(scene)).model;
    Workspace ws(m);
    TreeCholesky tree(m);
    ConstrainedSolve sparse(m);
    LoopState ls(m);
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd q, u;
      randomState(m, rng, q, u);
      if (m.nq != m.nu) q = m.q0();  // quaternion joints: the closed start, u random
      formEquations(m, q.data(), u.data(), ws);
      formLoops(m, ws, u.data(), ls);
      REQUIRE(tree.factor(ws.A));
      const Eigen::MatrixXd AinvGt = ws.A.llt().solve(ls.G.transpose());
      const double shift = 1e-6 * std::max(1e-300, (ls.G * AinvGt).diagonal().maxCoeff());
      const Eigen::VectorXd r = Eigen::VectorXd::Random(m.loop_rows);
      const Eigen::MatrixXd P = ws.A + ls.G.transpose() * ls.G / shift;
      const Eigen::VectorXd dense = P.llt().solve(ls.G.transpose() * r / shift);
      Eigen::VectorXd out(m.nu);
      sparse.factorPenalty(ls, tree, shift);
      sparse.penaltySolve(tree, r, out);
      INFO(scene << " trial " << trial);
      CHECK(relGap(out, dense) < kPenaltyRoundOff);
      const Eigen::VectorXd extra = Eigen::VectorXd::Random(m.nu).cwiseAbs();
      REQUIRE(tree.factor(ws.A, extra));
      Eigen::VectorXd x = ws.B;
      tree.solveInPlace(x.data());
      const Eigen::MatrixXd Abar = ws.A + Eigen::MatrixXd(extra.asDiagonal());
      CHECK(relGap(x, Abar.llt().solve(ws.B)) < kRoundOff);
    }
  }
}

TEST_CASE("formLoops touches only each loop's speeds and leaves nothing from the last state", "[mechanism]") {
  std::mt19937 rng(3);
  const Model m = loadScene(test::sourcePath("tests/scenes/mechanisms/bead_on_rail.json")).model;  // a slider: point and frame rows
  REQUIRE(m.loop_rows == 5);
  Workspace ws(m);
  LoopState reused(m);
  Eigen::VectorXd q, u;
  for (int trial = 0; trial < 3; ++trial) {
    randomState(m, rng, q, u);
    formKinematics(m, q.data(), u.data(), ws);
    formLoops(m, ws, u.data(), reused);
    LoopState fresh(m);
    formLoops(m, ws, u.data(), fresh);
    CHECK(reused.G == fresh.G);
    CHECK(reused.Gu == fresh.Gu);
    CHECK((fresh.Gu - fresh.G * u).cwiseAbs().maxCoeff() < 1e-12 * std::max(1.0, fresh.Gu.cwiseAbs().maxCoeff()));
  }
  // Every nonzero of G lies on its loop's speeds.
  int r = 0;
  for (size_t l = 0; l < m.loops.size(); ++l) {
    const int rows = loopRow(m.loops[l].type).equations;
    for (int j = 0; j < m.nu; ++j) {
      const bool on = std::binary_search(m.loop_speeds[l].begin(), m.loop_speeds[l].end(), j);
      if (!on) CHECK(reused.G.col(j).segment(r, rows).cwiseAbs().maxCoeff() == 0);
    }
    r += rows;
  }
}

TEST_CASE("a row of 20 four-bars of other lengths and masses stays on its parallel branch at rk4 dt 1e-3", "[mechanism]") {
  // Cranks 0.7 m, 0.8 kg; couplers 1.3 m, 1.5 kg; B0 at 0.9 m/s. The tree-sparse route (classical, projection).
  const int n = 20;
  const double lc = 0.7, s = 1.3, mc = 0.8, mk = 1.5, v0 = 0.9;
  const Model m = buildModel(parseSceneSpec(fourBarRow(n, lc, s, mc, mk, v0)));
  REQUIRE(TreeCholesky::pays(m));
  const Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 1.0, 1e-3, 0.1)));
  REQUIRE_FALSE(tr.failed());
  // rk4's error at dt 1e-3 over 1 s is ~1e-11 rad here; the bar is the issue's, 1e-6 rad.
  const double psi = parallelBranch(n, lc, mc, mk, v0, 1.0);
  for (int i = 0; i <= n; ++i) {
    INFO("crank " << i);
    CHECK(std::abs(tr.q.back()[i] - psi) < 1e-6);
  }
  CHECK(tr.loops.position_m < 1e-10);
}

TEST_CASE("a run's sampled multipliers by the tree-sparse factors give the dense ones' closure forces", "[mechanism]") {
  // recordLoopSamples takes lambda from the sparse path where it pays (A02, N = 40):
  // G^T lambda equals the dense least-norm one's; the balls' rows out of the plane are 0 in both.
  const Model m = test::loadData("mechanisms/iftomm_a02_n40.json");
  REQUIRE(TreeCholesky::pays(m));
  Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 0.2, 1e-3, 0.1)));
  REQUIRE_FALSE(tr.failed());
  recordLoopSamples(m, tr);  // as runTrajectory does after every run
  REQUIRE(tr.loop_samples.size() == tr.size());
  const std::vector<int> pq = m.qFilePermutation(), pu = m.uFilePermutation();
  Workspace ws(m);
  for (size_t s = 0; s < tr.size(); ++s) {
    Eigen::VectorXd q(m.nq), u(m.nu);
    for (int k = 0; k < m.nq; ++k) q[pq[k]] = tr.q[s][k];
    for (int k = 0; k < m.nu; ++k) u[pu[k]] = tr.u[s][k];
    formEquations(m, q.data(), u.data(), ws);
    const ConstrainedEquations dense = constrainedAt(m, ws, u.data());
    const Eigen::VectorXd& lambda = tr.loop_samples[s].lambda;
    INFO("sample " << s);
    CHECK(relGap(dense.loops.G.transpose() * lambda, dense.loops.G.transpose() * dense.lambda) < kRoundOff);
    CHECK(relGap(lambda, dense.lambda) < kRoundOff);  // no redundant row but the zero ones: lambda itself agrees
  }
}
