// Tier 3 (cross-check): the in-house Wittenburg formation against an
// independent Simbody model of the same scene, state by state and over time.
#include <catch2/catch.hpp>

#include "reference/simbody.hpp"
#include "solver/formation.hpp"
#include "solver/integrate.hpp"
#include "solver/mechanism/projection.hpp"
#include "momenta.hpp"
#include "engines.hpp"
#include "support.hpp"

using namespace em;

namespace {

// Round-off bound of the issue: relative to the reference's own magnitude.
constexpr double kRel = 1e-12;
// Absolute floors: B and u' may vanish (u = 0, hanging still); below these
// magnitudes (N m, rad/s^2) an absolute error of kRel * floor is accepted.
constexpr double kFloorB = 1e-3, kFloorUdot = 1e-3;
constexpr int kStates = 20;

// In-house classical rk8pd and Simbody RK-Merson runs of one scene, both required ok.
std::pair<Trajectory, Trajectory> runBoth(const Model& m, double tol_inhouse, double tol_simbody, double t_end);

RunSpec rk8pd(double tol, double t_end) { return test::runSpec(Method::Classical, Integrator::RK8PD, t_end, tol); }

// Simbody at accuracy `tol` with one of its integrators.
RunSpec simbodyRun(Integrator integrator, double tol, double t_end) {
  return test::runSpec(em::test::method("simbody"), integrator, t_end, tol);
}

std::pair<Trajectory, Trajectory> runBoth(const Model& m, double tol_inhouse, double tol_simbody, double t_end) {
  Trajectory in = simulate(m, checked(rk8pd(tol_inhouse, t_end)));
  Trajectory sb = SimbodySystem(m).simulate(checked(simbodyRun(em::test::scheme("rkmerson"), tol_simbody, t_end)));
  REQUIRE(in.status() == Outcome::Ok);
  REQUIRE(sb.status() == Outcome::Ok);
  REQUIRE(in.size() == sb.size());
  return {std::move(in), std::move(sb)};
}

}  // namespace

TEST_CASE("A B udot energies and poses agree with Simbody at random states of every scene", "[crosscheck]") {
  std::mt19937 rng(3);
  for (const auto& name : test::dataScenes()) {
    const Model m = test::loadData(name);
    SimbodySystem ref(m);
    Workspace ws(m);
    Eigen::VectorXd q = m.q0(), u = m.u0();
    for (int k = 0; k <= kStates; ++k) {
      INFO(name << " state " << k);
      formEquations(m, q.data(), u.data(), ws);
      formEnergies(m, q.data(), ws);
      ref.setState(q, u);
      const Eigen::MatrixXd A = ref.massMatrix();
      const Eigen::VectorXd B = ref.rhs(), udot = ref.udot();
      CHECK(test::relErr(ws.A, A) <= kRel);
      CHECK(test::relErr(ws.B, B, kFloorB) <= kRel);
      CHECK(test::relErr(Eigen::VectorXd(ws.A.llt().solve(ws.B)), udot, kFloorUdot) <= test::udotTolerance(A, kRel));
      CHECK(std::abs(ws.kinetic - ref.kineticEnergy()) <= kRel * std::max(ref.kineticEnergy(), 1.0));
      CHECK(std::abs(ws.potential - ref.potentialEnergy()) <= kRel * std::max(std::abs(ref.potentialEnergy()), 1.0));
      const std::vector<Pose> poses = ref.poses();
      for (int i = 0; i < m.n(); ++i) {
        CHECK((poses[i].p - ws.r[i]).norm() <= 1e-14 * std::max(1.0, ws.r[i].norm()));
        CHECK(rotationAngleBetween(quatToMatrix(poses[i].quat), ws.R[i]) <= 1e-14);
      }
      test::randomState(m, rng, q, u);
    }
  }
}

TEST_CASE("state mapping round-trips for every joint kind (quaternion order - ball speeds)", "[crosscheck]") {
  const Model m = test::loadData("tree_mixed.json");
  SimbodySystem ref(m);
  std::mt19937 rng(5);
  Eigen::VectorXd q, u, q2, u2;
  test::randomState(m, rng, q, u);
  ref.setState(q, u);
  ref.getState(q2, u2);
  CHECK((q2 - q).cwiseAbs().maxCoeff() < 1e-15);
  CHECK(u2 == u);
}

TEST_CASE("a balls u is the angular velocity in the parent frame in Simbody too", "[crosscheck]") {
  // One asymmetric body on a ball at the origin: its kinetic energy is
  // 1/2 w^T (R J R^T + pivot terms) w with w = u only if u is in the parent frame.
  const Model m = test::loadData("pendulum5_ball.json");
  SimbodySystem ref(m);
  Workspace ws(m);
  Eigen::VectorXd q = m.q0(), u = Eigen::VectorXd::Zero(m.nu);
  u.head<3>() = Vec3(0.3, -1.1, 0.7);
  ref.setState(q, u);
  formKinematics(m, q.data(), u.data(), ws);
  formEnergies(m, q.data(), ws);
  CHECK((ws.omega[0] - Vec3(0.3, -1.1, 0.7)).norm() < 1e-15);
  CHECK(std::abs(ref.kineticEnergy() - ws.kinetic) < 1e-13);
}

TEST_CASE("pendulum5 trajectory: in-house rk8pd 1e-13 vs Simbody RK-Merson 1e-12 over 5 s", "[crosscheck][slow]") {
  const auto [in, sb] = runBoth(test::loadData("pendulum5.json"), 1e-13, 1e-12, 5.0);
  double dq = 0;
  for (size_t k = 0; k < in.size(); ++k) dq = std::max(dq, (in.q[k] - sb.q[k]).cwiseAbs().maxCoeff());
  CHECK(dq <= 1e-6);
  CHECK(test::maxPoseDiff(in, sb) <= 1e-6);
}

TEST_CASE("ball-rooted and gimbal-rooted pendulum5 give the same body poses over 5 s", "[crosscheck][slow]") {
  const Model g = test::loadData("pendulum5.json"), b = test::loadData("pendulum5_ball.json");
  const Trajectory sg = SimbodySystem(g).simulate(checked(simbodyRun(em::test::scheme("rkmerson"), 1e-12, 5.0)));
  const Trajectory sball = SimbodySystem(b).simulate(checked(simbodyRun(em::test::scheme("rkmerson"), 1e-12, 5.0)));
  const Trajectory ib = simulate(b, checked(rk8pd(1e-13, 5.0)));
  CHECK(test::maxPoseDiff(sg, sball) <= 1e-8);
  CHECK(test::maxPoseDiff(ib, sball) <= 1e-8);
}

TEST_CASE("a branched tree with every joint kind tracks Simbody over 2 s", "[crosscheck][slow]") {
  const auto [in, sb] = runBoth(test::loadData("tree_mixed.json"), 1e-12, 1e-11, 2.0);
  CHECK(test::maxPoseDiff(in, sb) <= 1e-6);
}

TEST_CASE("a free-floating arm in zero gravity: Simbody and the in-house run keep its momenta and agree", "[crosscheck][sliding]") {
  // floating_arm: a free base, revolute, universal and prismatic joints, a
  // spring (an internal force): p and H about the origin are invariants.
  // Each engine's drift is its integrator's error at tol 1e-12 (measured
  // below 1e-11 for both); the two runs agree to the same level over 10 s.
  const Model m = test::loadData("floating_arm.json");
  const auto [in, sb] = runBoth(m, 1e-13, 1e-12, 10.0);
  for (const Trajectory* tr : {&in, &sb}) {
    const auto [dp, dH] = test::momentumDrift(m, *tr);
    INFO(tr->method() << ": |dp|/|p| " << dp << ", |dH|/|H| " << dH);
    CHECK(dp <= 1e-11);
    CHECK(dH <= 1e-11);
  }
  CHECK(test::maxPoseDiff(in, sb) <= 1e-8);
}

TEST_CASE("dampers: both engines close the energy balance and agree on the dissipated work", "[crosscheck][energy]") {
  // spring_damper over 5 s dissipates ~11 J of E_scale 16.7 J. At in-house
  // rk8pd 1e-12 and Simbody accuracy 1e-10 each balance closes to its
  // integration error (measured 5e-14 J and 6e-10 J; W_diss differs by 4e-10 J
  // between them): the bound leaves 100x over Simbody's.
  const auto [in, sb] = runBoth(test::loadData("spring_damper.json"), 1e-12, 1e-10, 5.0);
  constexpr double kBalance = 6e-8;  // J
  for (const Trajectory* t : {&in, &sb})
    for (size_t k = 0; k < t->size(); ++k) CHECK(std::abs(t->energy[k] + t->dissipated[k] - t->energy[0]) < kBalance);
  for (size_t k = 0; k < in.size(); ++k) CHECK(std::abs(in.dissipated[k] - sb.dissipated[k]) < kBalance);
  CHECK(in.dissipated.back() > 10.0);  // it does dissipate
}

TEST_CASE("Simbody RK-Merson - RK3 and CPodes agree with each other on pendulum5 over 1 s", "[crosscheck]") {
  const Model m = test::loadData("pendulum5.json");
  SimbodySystem ref(m);
  const Trajectory a = ref.simulate(checked(simbodyRun(em::test::scheme("rkmerson"), 1e-10, 1.0)));
  for (Integrator integ : {em::test::scheme("rk3"), em::test::scheme("cpodes")}) {
    const Trajectory b = ref.simulate(checked(simbodyRun(integ, 1e-10, 1.0)));
    INFO(integratorName(integ));
    REQUIRE(b.status() == Outcome::Ok);
    CHECK(b.run.integrator == integ);
    CHECK(test::maxPoseDiff(a, b) < 1e-6);  // both at accuracy 1e-10 over 1 s; measured ~1e-8
  }
  // An in-house integrator is not Simbody's: refused, naming Simbody's.
  RunSpec other = simbodyRun(Integrator::RK8PD, 1e-10, 1.0);
  CHECK_THROWS_WITH(ref.simulate(checked(other)), Catch::Contains("integrator 'rk8pd'") && Catch::Contains("rkmerson, rk3, cpodes"));
}

TEST_CASE("a Simbody failure is a one-line cause with its time - not an exception", "[crosscheck][failure]") {
  SceneSpec s = test::chainSpec(2);
  s.bodies[1].joint.u0 = Eigen::VectorXd::Constant(1, 1e200);  // kinetic energy overflows
  const Model m = buildModel(s);
  const Trajectory t = SimbodySystem(m).simulate(checked(simbodyRun(em::test::scheme("rkmerson"), 1e-10, 0.1)));
  CHECK(t.status() == Outcome::Failed);
  CHECK(t.failure_time == 0.0);
  CHECK_THAT(t.failure, Catch::StartsWith("Simbody: "));
  CHECK(t.failure.find('\n') == std::string::npos);
  CHECK(t.size() == 1);  // the initial sample only
}

// A mechanism (docs/reference-engines.md, "Mechanisms"): Simbody closes the
// loops with its own constraints (Ball; a hinge as a Ball and two
// ConstantAngle; Weld), point springs as TwoPointLinearSpring/Damper and
// drives as MobilityConstantForce. Its constrained u' at consistent states
// (the samples of an in-house run held on the manifold by the projection)
// against the in-house multipliers' (theory.md eq. (M7)).
TEST_CASE("Simbody's constrained u' equals the in-house one at 20 consistent states of the shipped mechanisms", "[simbody][mechanism]") {
  struct Case {
    const char* scene;
    double t_end;
  };
  for (const Case c : {Case{"mechanisms/andrews.json", 0.03}, Case{"mechanisms/iftomm_a02_n2.json", 1.0}, Case{"mechanisms/iftomm_a04.json", 4.0}}) {
    INFO(c.scene);
    const Model m = test::loadData(c.scene);
    REQUIRE(m.nq == m.nu);  // revolute joints only: q's file order is u's
    const Trajectory tr = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK8PD, c.t_end, 1e-11, c.t_end / kStates)));
    REQUIRE(tr.status() == Outcome::Ok);
    REQUIRE(tr.size() == kStates + 1);
    const std::vector<int> p = m.uFilePermutation();
    SimbodySystem sb(m);
    Workspace ws(m);
    double worst = 0;
    for (size_t s = 1; s < tr.size(); ++s) {
      Eigen::VectorXd q(m.nq), u(m.nu);
      for (int i = 0; i < m.nu; ++i) {
        q[p[i]] = tr.q[s][i];
        u[p[i]] = tr.u[s][i];
      }
      formEquations(m, q.data(), u.data(), ws);
      const ConstrainedEquations in = constrainedAt(m, ws, u.data());
      sb.setState(q, u);
      const Eigen::VectorXd theirs = sb.udot();
      const double scale = std::max(in.udot.cwiseAbs().maxCoeff(), kFloorUdot);
      worst = std::max(worst, (theirs - in.udot).cwiseAbs().maxCoeff() / scale);
    }
    // Round-off times the conditioning of G A^-1 G^T (Andrews' lever arms span
    // 1e-3 to 7e-2 m): measured 6.9e-14 (A02), 4.5e-13 (A04), 6.4e-13 (Andrews).
    INFO("worst relative u' difference " << worst);
    CHECK(worst < 1e-10);
  }
}

TEST_CASE("Simbody runs Andrews' squeezer to the published solution, its drive and spring in the energy balance", "[simbody][mechanism]") {
  const Model m = test::loadData("mechanisms/andrews.json");
  const Trajectory sb = SimbodySystem(m).simulate(checked(simbodyRun(em::test::scheme("rkmerson"), 1e-10, 0.03)));
  REQUIRE(sb.status() == Outcome::Ok);
  // The IVP test set's SOLN at 0.03 s (andrews.json's x-reference); measured 3.4e-10 relative at worst.
  const double soln[7] = {15.81077119629904, -15.75637105984298, 0.04082224013073101, -0.5347301163226948,
                          0.5244099658805304, 0.5347301163226948, 1.048080741042263};
  for (int k = 0; k < 7; ++k) CHECK(std::abs(sb.q.back()[k] - soln[k]) <= 1e-8 * std::abs(soln[k]));
  // E + W_diss (the drive's work negative): measured 1.1e-9 J of ~1.5 J.
  for (size_t s = 0; s < sb.size(); ++s) CHECK(std::abs(sb.energy[s] + sb.dissipated[s] - sb.energy[0]) < 1e-7);
  REQUIRE(sb.has_loops);
  CHECK(sb.loops.position_m < 1e-10);  // Simbody projects to its accuracy: measured 7.7e-12 m
}

// A weld and a hinge that carry the motion (tests/scenes/mechanisms/
// door_and_plate.json: a plate on a free joint welded to a revolute arm, a
// door on a free joint hinged to the ground about a tilted axis). Oracle: the
// arm and the welded plate turn as one rigid body about the arm's fixed axis
// z, so theta'' = tau_z / I_z exactly (the axial part of Euler's equations,
// I_z = sum z^T J z + m |z x (r - p)|^2, tau_z = sum z . ((r - p) x m g)); the
// door likewise about its hinge axis. At random states projected onto the loops.
TEST_CASE("a welded plate and a hinged door turn as rigid bodies about their fixed axes, in-house and in Simbody", "[simbody][mechanism]") {
  const Model m = loadScene(test::sourcePath("tests/scenes/mechanisms/door_and_plate.json")).model;
  const auto body = [&](const char* name) {
    for (int i = 0; i < m.n(); ++i)
      if (m.bodies[i].name == name) return i;
    FAIL("no body " << name);
    return -1;
  };
  const int arm = body("arm"), plate = body("plate"), door = body("door");
  Workspace ws(m);
  LoopProjector project(m);
  SimbodySystem sb(m);
  std::mt19937 rng(5);
  // (axis, pivot) -> tau / I over the given bodies at the state ws holds.
  const auto fixedAxis = [&](const Vec3& z, const Vec3& p, std::initializer_list<int> bodies) {
    double I = 0, tau = 0;
    for (int b : bodies) {
      const Vec3 r = ws.r[b] - p;
      I += z.dot(ws.J_w[b] * z) + m.bodies[b].mass * z.cross(r).squaredNorm();
      tau += z.dot(r.cross(m.bodies[b].mass * m.gravity));
    }
    return tau / I;
  };
  int states = 0;
  for (int draw = 0; draw < 2000 && states < 20; ++draw) {  // most draws land far from the weld: projection fails, drawn again
    Eigen::VectorXd q, u;
    randomState(m, rng, q, u);
    if (!project.positions(m, ws, q.data(), u.data(), 1e-12, 50).converged) continue;
    project.velocities(u.data());
    ++states;
    formEquations(m, q.data(), u.data(), ws);
    const ConstrainedEquations in = constrainedAt(m, ws, u.data());
    sb.setState(q, u);
    const Eigen::VectorXd theirs = sb.udot();
    // The arm's angle: theta'' about its fixed axis (z, through its joint point).
    const double arm_exact = fixedAxis(Vec3::UnitZ(), ws.o[arm], {arm, plate});
    // The door's angular acceleration along its hinge axis (its u: v of the hinge point, then omega in the world).
    const Vec3 axis = Vec3(0.6, 0, 0.8);
    const double door_exact = fixedAxis(axis, ws.o[door], {door});
    const int ia = m.bodies[arm].iu, id = m.bodies[door].iu + 3;
    const double turn = std::acos(std::clamp(((ws.R[arm].transpose() * ws.R[plate]).trace() - 1) / 2, -1.0, 1.0));
    INFO("state " << states << " (plate turned from its weld by " << turn << " rad): arm exact " << arm_exact << " in-house " << in.udot[ia] << " simbody " << theirs[ia]
                  << "; door exact " << door_exact << " in-house " << axis.dot(in.udot.segment<3>(id)) << " simbody "
                  << axis.dot(theirs.segment<3>(id)));
    // Round-off: I and tau are sums of O(1) terms; the solves' conditioning stays below 1e4 here.
    CHECK(std::abs(in.udot[ia] - arm_exact) < 1e-10 * std::abs(arm_exact) + 1e-10);
    CHECK(std::abs(theirs[ia] - arm_exact) < 1e-10 * std::abs(arm_exact) + 1e-10);
    CHECK(std::abs(axis.dot(in.udot.segment<3>(id)) - door_exact) < 1e-10 * std::abs(door_exact) + 1e-10);
    CHECK(std::abs(axis.dot(theirs.segment<3>(id)) - door_exact) < 1e-10 * std::abs(door_exact) + 1e-10);
  }
  CHECK(states == 20);
}
