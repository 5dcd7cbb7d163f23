// The Wittenburg formation: closed-form cases (tier 1) and identities between
// its parts (tier 2): barycentric K = naive K, A SPD, A' = d/dt A, the
// energy identity, power balance, and no allocation per evaluation.
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <new>

#include "solver/dynamics.hpp"
#include "solver/applied_forces.hpp"
#include "solver/dense_oracles.hpp"
#include "solver/formation.hpp"
#include "support.hpp"

// Counting allocator: every heap allocation in this test binary is counted.
// Every replaceable form is replaced (plain, array, nothrow, sized), so that
// no pair mixes ours with the library's (ASan reports such mismatches).
// Over-aligned forms are left to the library: Eigen's fixed-size types here
// need no more than the default alignment.
// GCC 12 takes free() of what this operator new returned for a mismatch
// (-Wmismatched-new-delete) once inlined into library code; both are ours and match.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
static std::atomic<long> g_allocations{0};
static void* countedAlloc(std::size_t n) noexcept {
  ++g_allocations;
  return std::malloc(n ? n : 1);
}
void* operator new(std::size_t n) {
  if (void* p = countedAlloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  if (void* p = countedAlloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return countedAlloc(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return countedAlloc(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

using namespace em;

namespace {

// Round-off of sums of O(n) products of unit-size terms.
constexpr double kRoundoff = 1e-13;
// Random states per scene for the identity checks.
constexpr int kStates = 20;

Workspace formAt(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u, bool adot = false) {
  Workspace ws(m);
  formEquations(m, q.data(), u.data(), ws, adot);
  formEnergies(m, q.data(), ws);
  return ws;
}

// The same with the dense oracles' K and K_T formed too.
std::pair<Workspace, test::DenseK> formDenseAt(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  Workspace ws = formAt(m, q, u, true);
  test::DenseK dk = test::formDenseK(m, ws);
  return {std::move(ws), std::move(dk)};
}

// Every data scene at its initial and kStates random states; `rotational_only`
// leaves out the sliding scenes (the dense oracles are eq. (2)'s, of rotations).
template <class F>
void forEachState(F&& f, bool rotational_only = false) {
  std::mt19937 rng(20261122);
  for (const auto& name : test::dataScenes()) {
    const Model m = test::loadData(name);
    if (rotational_only && m.has_sliding) continue;
    Eigen::VectorXd q = m.q0(), u = m.u0();
    for (int k = 0; k <= kStates; ++k) {
      INFO(name << " state " << k);
      f(m, q, u);
      test::randomState(m, rng, q, u);
    }
  }
}

SceneSpec revoluteSpec(int n) {
  SceneSpec s;
  s.name = "planar";
  for (int i = 0; i < n; ++i) {
    BodySpec b;
    b.name = "b" + std::to_string(i);
    b.parent = i ? "b" + std::to_string(i - 1) : "ground";
    b.joint.type = JointType::Revolute;
    b.joint.axis[0] = Vec3::UnitX();
    b.joint.q0 = Eigen::VectorXd::Zero(1);
    b.joint.u0 = Eigen::VectorXd::Zero(1);
    s.bodies.push_back(b);
  }
  return s;
}

}  // namespace

TEST_CASE("compound pendulum: A = I + m l2 and udot = -m g l sin q / (I + m l2)", "[closedform][formation]") {
  const double m = 2.5, l = 0.7, I = 0.11, g = 9.81, q = 0.9, u = -1.3;
  SceneSpec s = revoluteSpec(1);
  s.bodies[0].mass = m;
  s.bodies[0].inertia = Vec3(I, 0.2, 0.2).asDiagonal();
  s.bodies[0].joint.in_body = Vec3(0, 0, l);  // CM a distance l below the pivot at q = 0
  const Model model = buildModel(s);
  const Eigen::VectorXd qv = Eigen::VectorXd::Constant(1, q), uv = Eigen::VectorXd::Constant(1, u);
  const Workspace ws = formAt(model, qv, uv);
  CHECK(std::abs(ws.A(0, 0) - (I + m * l * l)) < kRoundoff);
  CHECK(std::abs(ws.B[0] / ws.A(0, 0) - (-m * g * l * std::sin(q) / (I + m * l * l))) < kRoundoff);
  CHECK(std::abs(ws.kinetic - 0.5 * (I + m * l * l) * u * u) < kRoundoff);
  CHECK(std::abs(ws.potential - (-m * g * l * std::cos(q))) < kRoundoff);
}

TEST_CASE("a planar joint: a body slides in its plane under gravity and its springs and turns about the normal", "[closedform][formation]") {
  // One body on a planar joint with its CM a lever c off the joint point, in the plane:
  // r = s1 e1 + s2 e2 - R(theta) c, R about n = e1 x e2. Lagrange's equations give
  //   A = [[m, 0, m e1.k], [0, m, m e2.k], [., ., J_n + m |c|^2]],  k = d(-R c)/dtheta = -n x R c,
  //   r'' = s'' + theta'' k + theta'^2 R c (the CM's centripetal acceleration points at the joint
  //   point, -theta'^2 (r - s)), so B_i = e_i.(m g - m theta'^2 R c) - k_i (s_i - rest_i) and
  //   B_theta = k.(m g) - k3 (theta - rest_3) (R c . k = 0), J_n = n.J_w n (J_w in the world axes).
  const double m = 1.7, th = 0.8, thd = -1.3;
  const Vec3 e1 = Vec3(0.6, 0.8, 0), e2 = Vec3(0, 0, 1), n = e1.cross(e2), g(0.2, -9.81, 0.4), c = 0.3 * e1 - 0.1 * e2;
  SceneSpec s;
  s.name = "planar_body";
  s.gravity = g;
  BodySpec b;
  b.name = "sled";
  b.parent = "ground";
  b.mass = m;
  b.inertia << 0.05, 0.003, -0.002, 0.003, 0.06, 0.001, -0.002, 0.001, 0.04;
  b.joint.type = JointType::Planar;
  b.joint.axis[0] = e1;
  b.joint.axis[1] = e2;
  b.joint.in_body = c;  // body frame = world at theta = 0
  b.joint.q0 = Eigen::Vector3d(0.4, -0.25, th);
  b.joint.u0 = Eigen::Vector3d(0.7, 0.2, thd);
  b.joint.has_spring = true;
  b.joint.spring = {Eigen::Vector3d(20, 5, 2), Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, 0, 0.3)};
  s.bodies.push_back(b);
  const Model model = buildModel(s);
  const Workspace ws = formAt(model, model.q0(), model.u0());
  const Mat3 R = rot(n, th);
  const Vec3 Rc = R * c, k = -n.cross(Rc);
  const double Jn = n.dot(R * b.inertia * R.transpose() * n);
  Eigen::Matrix3d A;
  A << m, 0, m * e1.dot(k), 0, m, m * e2.dot(k), m * e1.dot(k), m * e2.dot(k), Jn + m * c.squaredNorm();
  const Vec3 f = m * g - m * thd * thd * Rc;  // gravity less the lever's centripetal term, on the joint point's slides
  const Vec3 B(e1.dot(f) - 20 * (0.4 - 0.1), e2.dot(f) - 5 * (-0.25), k.dot(m * g) - 2 * (th - 0.3));
  CHECK((ws.A - A).cwiseAbs().maxCoeff() < kRoundoff);
  CHECK((ws.B - B).cwiseAbs().maxCoeff() < 10 * kRoundoff);
  const Eigen::Vector3d u = model.u0();
  CHECK(std::abs(ws.kinetic - 0.5 * u.dot(A * u)) < kRoundoff);
}

TEST_CASE("a free asymmetric rotor on a ball and on a gimbal obeys Euler's equations J w' = -w x J w", "[closedform][formation]") {
  // One body held at its CM (joint point = CM): gravity has no moment, so u'
  // is the torque-free rotor's. World frame: J_w w' = -w x J_w w with
  // J_w = R J R^T. The gyroscopic term is the whole right-hand side here, so a
  // wrong sign or factor in B's w x J w fails at once; the planar closed forms
  // above cannot see it (w x J w = 0 there). 1e-12 relative: a few dozen
  // products of O(1) numbers.
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> uni(-1.5, 1.5);
  for (JointType type : {JointType::Ball, JointType::Gimbal}) {
    SceneSpec s = revoluteSpec(1);
    s.bodies[0].inertia = Vec3(0.3, 0.5, 0.65).asDiagonal();  // asymmetric, within the triangle inequality
    s.bodies[0].inertia(0, 1) = s.bodies[0].inertia(1, 0) = 0.04;  // and not principal in the body frame
    s.bodies[0].joint.type = type;
    s.bodies[0].joint.in_body = Vec3::Zero();
    s.bodies[0].joint.q0 = type == JointType::Ball ? Eigen::VectorXd(Eigen::Vector4d(1, 0, 0, 0)) : Eigen::VectorXd::Zero(3);
    s.bodies[0].joint.u0 = Eigen::VectorXd::Zero(3);
    const Model model = buildModel(s);
    for (int k = 0; k < 20; ++k) {
      Eigen::VectorXd q(model.nq), u(3);
      for (int i = 0; i < model.nq; ++i) q[i] = uni(rng);
      if (type == JointType::Ball) q.normalize();
      else q[1] *= 0.9;  // away from gimbal lock
      for (int i = 0; i < 3; ++i) u[i] = 3 * uni(rng);
      const Workspace ws = formAt(model, q, u);
      const Eigen::VectorXd udot = ws.A.llt().solve(ws.B);
      const Mat3& Jw = ws.J_w[0];
      const Vec3 w = ws.omega[0];
      const Vec3 wdot_euler = Jw.llt().solve(Vec3(-w.cross(Jw * w)));
      const Vec3 wdot = ws.P * udot + ws.Pdot * u;  // w = P u, so w' = P u' + P' u
      INFO(jointTypeName(type) << " state " << k << ": " << wdot.transpose() << " vs " << wdot_euler.transpose());
      CHECK((wdot - wdot_euler).norm() < 1e-12 * std::max(1.0, wdot_euler.norm()));
      CHECK(wdot_euler.norm() > 1e-2);  // not vacuous: the rotor precesses
    }
  }
}

TEST_CASE("planar double pendulum of point masses matches the textbook equations", "[closedform][formation]") {
  // Point masses: inertia eps about the CM; its effect on u' is O(eps / (m l^2)).
  const double m1 = 1.3, m2 = 0.8, l1 = 1.1, l2 = 0.6, g = 9.81, eps = 1e-12;
  const double kPointMassTol = 1e-9;
  SceneSpec s = revoluteSpec(2);
  s.bodies[0].mass = m1;
  s.bodies[1].mass = m2;
  for (auto& b : s.bodies) b.inertia = eps * Mat3::Identity();
  s.bodies[0].joint.in_body = Vec3(0, 0, l1);
  s.bodies[1].joint.in_parent = Vec3::Zero();  // joint 2 sits at mass 1
  s.bodies[1].joint.in_body = Vec3(0, 0, l2);
  const Model model = buildModel(s);
  const double q1 = 0.4, q2 = -1.1, u1 = 0.7, u2 = 1.9;
  const Workspace ws = formAt(model, Eigen::Vector2d(q1, q2), Eigen::Vector2d(u1, u2));
  const Eigen::Vector2d qdd = ws.A.llt().solve(ws.B);
  // Textbook form in absolute angles th1 = q1, th2 = q1 + q2.
  const double t1 = q1, t2 = q1 + q2, w1 = u1, w2 = u1 + u2, d = t1 - t2;
  Eigen::Matrix2d M;
  M << (m1 + m2) * l1, m2 * l2 * std::cos(d), m2 * l1 * std::cos(d), m2 * l2;
  const Eigen::Vector2d rhs(-m2 * l2 * w2 * w2 * std::sin(d) - (m1 + m2) * g * std::sin(t1),
                            m2 * l1 * w1 * w1 * std::sin(d) - m2 * g * std::sin(t2));
  const Eigen::Vector2d tdd = M.lu().solve(rhs);
  CHECK(std::abs(qdd[0] - tdd[0]) < kPointMassTol * tdd.cwiseAbs().maxCoeff());
  CHECK(std::abs(qdd[0] + qdd[1] - tdd[1]) < kPointMassTol * tdd.cwiseAbs().maxCoeff());
}

TEST_CASE("barycentric K equals the naive triple sum", "[identity][formation]") {
  forEachState([](const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
    const auto [ws, dk] = formDenseAt(m, q, u);
    const Eigen::MatrixXd Kn = test::naiveK(m, ws);
    CHECK((dk.K - Kn).cwiseAbs().maxCoeff() <= kRoundoff * Kn.cwiseAbs().maxCoeff());
  }, true);
}

TEST_CASE("A from subtree sums equals the dense PT T K TT P of eq. 2", "[identity][formation]") {
  // Two evaluations of eq. (2): O(n depth) 3-vector products against the
  // dense T K T^T sweeps and 3x3 block projections; both sum O(n) terms.
  forEachState([](const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
    const auto [ws, dk] = formDenseAt(m, q, u);
    const Eigen::MatrixXd dense = test::denseA(m, dk);
    CHECK((ws.A - dense).cwiseAbs().maxCoeff() <= kRoundoff * dense.cwiseAbs().maxCoeff());
    CHECK(ws.A == ws.A.transpose());  // filled symmetrically, exactly
  }, true);
}

TEST_CASE("A' from subtree rates equals the dense one from K' and K_T", "[identity][formation]") {
  forEachState([](const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
    const auto [ws, dk] = formDenseAt(m, q, u);
    const Eigen::MatrixXd dense = test::denseAdot(m, ws, dk);
    CHECK((ws.Adot - dense).cwiseAbs().maxCoeff() <= kRoundoff * std::max(dense.cwiseAbs().maxCoeff(), 1.0));
    CHECK(ws.Adot == ws.Adot.transpose());
  }, true);
}

TEST_CASE("the O(n) product K x equals the dense one", "[identity][formation]") {
  // B's K phi without K (docs/theory.md §5), for any x: here a random one.
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  forEachState([&](const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
    auto [ws, dk] = formDenseAt(m, q, u);
    const Eigen::VectorXd x = Eigen::VectorXd::NullaryExpr(3 * m.n(), [&] { return gauss(rng); });
    Eigen::VectorXd Kx(3 * m.n());
    multiplyK(m, x, ws, Kx);
    const Eigen::VectorXd dense = dk.K * x;
    CHECK((Kx - dense).cwiseAbs().maxCoeff() <= kRoundoff * dk.K.cwiseAbs().maxCoeff() * x.cwiseAbs().maxCoeff());
  }, true);
}

TEST_CASE("A is symmetric positive definite and 1/2 uTAu is the kinetic energy", "[identity][formation]") {
  forEachState([](const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
    const Workspace ws = formAt(m, q, u);
    CHECK((ws.A - ws.A.transpose()).cwiseAbs().maxCoeff() <= kRoundoff * ws.A.cwiseAbs().maxCoeff());
    const Eigen::VectorXd lam = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(ws.A).eigenvalues();
    CHECK(lam.minCoeff() > 0);
    // Kinetic energy from the body velocities, formed independently of A.
    CHECK(std::abs(0.5 * u.dot(ws.A * u) - ws.kinetic) <= kRoundoff * std::max(ws.kinetic, 1.0));
  });
}

TEST_CASE("Adot equals a central finite difference of A along the motion", "[identity][formation]") {
  // Central difference: truncation O(h^2 |A'''|) ~ 1e-10, round-off eps |A| / h ~ 1e-11.
  const double h = 1e-5, kFdRel = 1e-6;
  forEachState([&](const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
    const Workspace ws = formAt(m, q, u, true);
    Eigen::VectorXd qdot(m.nq);
    formQdot(m, q.data(), u.data(), qdot.data());
    const Eigen::MatrixXd fd = (formAt(m, q + h * qdot, u).A - formAt(m, q - h * qdot, u).A) / (2 * h);
    CHECK((ws.Adot - fd).cwiseAbs().maxCoeff() <= kFdRel * std::max(fd.cwiseAbs().maxCoeff(), 1.0));
  });
}

TEST_CASE("power balance: uT B + uT Adot u / 2 + dV/dt = -(damper power)", "[identity][formation]") {
  // d/dt (1/2 u^T A u + V) = u^T (A u' ) + 1/2 u^T A' u + V' and A u' = B.
  forEachState([](const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
    const Workspace ws = formAt(m, q, u, true);
    double Vdot = 0, damping = 0, scale = 0;
    for (int i = 0; i < m.n(); ++i) {
      const Body& b = m.bodies[i];
      Vdot -= b.mass * m.gravity.dot(ws.v[i]);
      scale += std::abs(b.mass * m.gravity.dot(ws.v[i]));
      if (!b.joint.has_spring) continue;
      for (int k = 0; k < b.nu(); ++k) {
        Vdot += b.joint.spring.k[k] * (q[b.iq + k] - b.joint.spring.q_rest[k]) * u[b.iu + k];
        damping += b.joint.spring.c[k] * u[b.iu + k] * u[b.iu + k];
      }
    }
    const double residual = u.dot(ws.B) + 0.5 * u.dot(ws.Adot * u) + Vdot + damping;
    scale += std::abs(u.dot(ws.B)) + std::abs(0.5 * u.dot(ws.Adot * u)) + damping;
    CHECK(std::abs(residual) <= 1e-12 * std::max(scale, 1.0));
  });
}

TEST_CASE("only declared terms are built: springs only when a scene has them", "[formation]") {
  CHECK_FALSE(test::loadData("pendulum5.json").has_springs);
  const Model m = test::loadData("spring_damper.json");
  REQUIRE(m.has_springs);
  // With the springs' B part removed, B equals that of the same model without springs.
  Model bare = m;
  bare.has_springs = false;
  const Eigen::VectorXd q = m.q0(), u = m.u0();
  Eigen::VectorXd Q = Eigen::VectorXd::Zero(m.nu);
  addSpringForces(m, q.data(), u.data(), Q);
  CHECK(Q.norm() > 1.0);
  CHECK((formAt(m, q, u).B - formAt(bare, q, u).B - Q).norm() <= kRoundoff * Q.norm());
}

TEST_CASE("an evaluation of any method allocates nothing on the heap", "[identity][formation][allocation]") {
  // chain50: N = 52, large enough for Eigen's blocked products and Cholesky.
  for (const char* scene : {"pendulum5.json", "tree_mixed.json", "chain10.json", "chain50.json"}) {
    const Model m = test::loadData(scene);
    for (const MethodInfo& row : methodTable()) {  // every in-house method of the registry
      if (row.engine != Engine::InHouse || !row.make) continue;  // (a row another test adds for one call has no code)
      const Method method = row.id;
      for (int refine : {0, 2}) {  // with and without residual corrections (the option "refine")
        MethodOptions opt;
        opt.params["refine"] = refine;
        Dynamics dyn(m, method, opt);
        Eigen::VectorXd y = dyn.initialState(m.q0(), m.u0()), dy(dyn.size());
        REQUIRE(dyn.rhs(0, y.data(), dy.data()));  // warm-up
        const long before = g_allocations.load();
        for (int k = 0; k < 10; ++k) dyn.rhs(0, y.data(), dy.data());
        StepInfo step;
        dyn.afterStep(0, y.data(), step);
        const long allocations = g_allocations.load() - before;  // read before INFO allocates
        INFO(scene << " " << methodName(method) << " refine " << refine);
        CHECK(allocations == 0);
      }
    }
  }
  // A mechanism over A's tree-sparse factors (docs/theory.md §16): the
  // multipliers at every evaluation and the projection after a step.
  const Model m = test::loadData("mechanisms/iftomm_a02_n40.json");
  for (Method method : {Method::Classical, Method::Articulated}) {
    Dynamics dyn(m, method);
    Eigen::VectorXd y = dyn.initialState(m.q0(), m.u0()), dy(dyn.size());
    REQUIRE(dyn.rhs(0, y.data(), dy.data()));
    StepInfo step;
    REQUIRE(dyn.afterStep(0, y.data(), step));
    const long before = g_allocations.load();
    for (int k = 0; k < 10; ++k) dyn.rhs(0, y.data(), dy.data());
    dyn.afterStep(0, y.data(), step);
    const long allocations = g_allocations.load() - before;
    INFO("A02 (N = 40) " << methodName(method));
    CHECK(allocations == 0);
  }
}
