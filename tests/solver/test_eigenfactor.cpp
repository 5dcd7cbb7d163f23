// The Junkins–Schaub pieces on hand-made matrices: Jacobi correction,
// symmetric orthonormalization, the off-diagonal norm, and the rates near an
// eigenvalue crossing (closed form: |Omega| = delta / (2 (t^2 + delta^2))).
#include <catch2/catch.hpp>

#include <random>

#include "solver/eigenfactor_ops.hpp"

using namespace em;

namespace {

constexpr int N = 7;

Eigen::MatrixXd randomSpd(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Eigen::MatrixXd X(N, N);
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) X(i, j) = g(rng);
  return X * X.transpose() + Eigen::MatrixXd::Identity(N, N);
}

RowMatrix eigenRows(const Eigen::MatrixXd& A) {
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvectors().transpose();
}

}  // namespace

TEST_CASE("offDiagonalNorm is accurate for a nearly diagonal matrix", "[closedform][eigenfactor]") {
  // Regression: ||D||^2 - ||diag D||^2 loses everything below eps ||D||^2.
  Eigen::MatrixXd D = 1e3 * Eigen::MatrixXd::Identity(3, 3);
  D(0, 1) = D(1, 0) = 3e-12;
  D(1, 2) = D(2, 1) = 4e-12;
  CHECK(std::abs(offDiagonalNorm(D) - std::sqrt(2.0) * 5e-12) < 1e-26);
}

TEST_CASE("Jacobi correction re-diagonalizes a perturbed eigenbasis", "[identity][eigenfactor]") {
  std::mt19937 rng(7);
  const Eigen::MatrixXd A = randomSpd(rng);
  RowMatrix C = eigenRows(A) + 1e-6 * Eigen::MatrixXd::Random(N, N);
  const double orth_before = (C * C.transpose() - Eigen::MatrixXd::Identity(N, N)).norm();
  Eigen::VectorXd lambda(N);
  CorrectionScratch w(N);
  const double tol = 1e-13;
  const JacobiStats st = jacobiCorrect(A, C, lambda, w, tol, 50);
  CHECK(st.converged);
  CHECK(st.sweeps >= 1);
  CHECK(st.sweeps <= 3);  // quadratic convergence from a warm start
  CHECK(offDiagonalNorm(C * A * C.transpose()) <= 2 * tol * A.norm());
  CHECK((lambda - (C * A * C.transpose()).diagonal()).cwiseAbs().maxCoeff() < 1e-13 * A.norm());
  // Rotations keep C C^T - I as it was: only orthonormalization mends it.
  CHECK(std::abs((C * C.transpose() - Eigen::MatrixXd::Identity(N, N)).norm() - orth_before) < 1e-13);
}

TEST_CASE("Jacobi from an exact eigenbasis needs at most one sweep", "[identity][eigenfactor]") {
  std::mt19937 rng(8);
  const Eigen::MatrixXd A = randomSpd(rng);
  RowMatrix C = eigenRows(A);
  Eigen::VectorXd lambda(N);
  CorrectionScratch w(N);
  CHECK(jacobiCorrect(A, C, lambda, w, 1e-13, 50).sweeps <= 1);
}

TEST_CASE("symmetric orthonormalization gives the nearest orthogonal matrix", "[identity][eigenfactor]") {
  std::mt19937 rng(9);
  const RowMatrix C0 = eigenRows(randomSpd(rng)) + 1e-4 * Eigen::MatrixXd::Random(N, N);
  RowMatrix C = C0;
  CorrectionScratch w(N);
  symmetricOrthonormalize(C, w);
  CHECK((C * C.transpose() - Eigen::MatrixXd::Identity(N, N)).norm() < 1e-14);
  // Nearer to C0 than Gram–Schmidt's orthonormalization of the same rows.
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(C0.transpose()).householderQ();
  Eigen::MatrixXd Qrows = Q.transpose();
  for (int i = 0; i < N; ++i)
    if (Qrows.row(i).dot(C0.row(i)) < 0) Qrows.row(i) *= -1;
  CHECK((C - C0).norm() <= (Qrows - C0).norm());
}

TEST_CASE("near an eigenvalue crossing |Omega| grows as delta / (2 (t2 + delta2))", "[closedform][eigenfactor]") {
  // A(t) = [[1 + t, delta], [delta, 1 - t]], A' = diag(1, -1): the eigenvectors
  // turn at phi' = -delta / (2 (t^2 + delta^2)); the gap is 2 sqrt(t^2 + delta^2).
  const double delta = 1e-3;
  Eigen::MatrixXd Om(2, 2), T(2, 2), Adot(2, 2);
  Adot << 1, 0, 0, -1;
  Eigen::VectorXd ld(2);
  RowMatrix Cd(2, 2);
  double previous = 0;
  for (double t : {1e-1, 1e-2, 1e-3, 0.0}) {
    Eigen::MatrixXd A(2, 2);
    A << 1 + t, delta, delta, 1 - t;
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
    const RowMatrix C = es.eigenvectors().transpose();
    const RateStatus st = eigenRates(C, es.eigenvalues(), Adot, 1e-12, Om, T, ld, Cd);
    REQUIRE(st.ok);
    const double exact = delta / (2 * (t * t + delta * delta));
    INFO("t = " << t);
    CHECK(std::abs(st.max_Omega - exact) < 1e-9 * exact);
    CHECK(st.max_Omega > previous);  // grows toward the crossing
    previous = st.max_Omega;
    // lambda' = -/+ t / sqrt(t^2 + delta^2): the eigenvalues' own rates.
    CHECK(std::abs(ld[1] - t / std::sqrt(t * t + delta * delta)) < 1e-9);
  }
  CHECK(previous == Approx(1.0 / (2 * delta)).epsilon(1e-9));
}

TEST_CASE("a gap below the floor stops the rates and names the pair", "[closedform][eigenfactor]") {
  Eigen::MatrixXd A(3, 3), Adot = Eigen::MatrixXd::Identity(3, 3), Om(3, 3), T(3, 3);
  A << 2, 0, 0, 0, 1 + 1e-14, 0, 0, 0, 1;
  Eigen::VectorXd ld(3);
  RowMatrix Cd(3, 3);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  const RateStatus st = eigenRates(es.eigenvectors().transpose(), es.eigenvalues(), Adot, 1e-12, Om, T, ld, Cd);
  CHECK_FALSE(st.ok);
  CHECK(st.i == 0);
  CHECK(st.j == 1);
  CHECK(st.gap < 1e-12);
  CHECK(minEigenGap(es.eigenvalues()) == Approx(1e-14).margin(1e-16));
}

TEST_CASE("each residual correction multiplies the error of u' by I - H A, H the eigenfactors' inverse", "[identity][eigenfactor][refine]") {
  // refineResidual (docs/theory.md §8): e_{k+1} = (I - H A) e_k exactly, so
  // |e_{k+1}| <= ||I - H A||_2 |e_k| up to rounding; H from eigenvalues off
  // by a relative 1e-3 and a slightly turned C.
  std::mt19937 rng(7);
  const Eigen::MatrixXd A = randomSpd(rng);
  const Eigen::VectorXd B = Eigen::VectorXd::LinSpaced(N, -1.0, 2.0);
  const Eigen::VectorXd exact = A.llt().solve(B);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  Eigen::MatrixXd turn = Eigen::MatrixXd::Zero(N, N);
  turn(0, 3) = 2e-4, turn(3, 0) = -2e-4;
  const RowMatrix C = (Eigen::MatrixXd::Identity(N, N) + turn) * es.eigenvectors().transpose();
  Eigen::VectorXd lambda = es.eigenvalues();
  for (int i = 0; i < N; ++i) lambda[i] *= 1 + (i % 2 ? 1e-3 : -1e-3);
  const auto applyH = [&](const Eigen::VectorXd& b, Eigen::Ref<Eigen::VectorXd> out) {
    out = C.transpose() * (lambda.cwiseInverse().asDiagonal() * (C * b));
  };
  const Eigen::MatrixXd H = C.transpose() * lambda.cwiseInverse().asDiagonal() * C;
  const double kappa = (Eigen::MatrixXd::Identity(N, N) - H * A).jacobiSvd().singularValues()[0];
  REQUIRE(kappa < 1e-2);
  const double kRounding = 1e-13 * exact.norm();  // a few hundred eps of |u'|: N^2 products
  std::vector<double> e;
  Eigen::VectorXd r(N), du(N);
  for (int steps = 0; steps <= 3; ++steps) {
    Eigen::VectorXd u(N);
    applyH(B, u);
    CHECK(refineResidual(A, B, steps, applyH, u, r, du));
    e.push_back((u - exact).norm());
  }
  INFO("errors " << e[0] << " " << e[1] << " " << e[2] << " " << e[3] << ", kappa " << kappa);
  CHECK(e[0] > 1e-4 * exact.norm());  // not vacuous: the unrefined u' is visibly off
  for (int k = 0; k < 3; ++k) CHECK(e[k + 1] <= kappa * e[k] * (1 + 1e-6) + kRounding);
  CHECK(e[2] <= 1e-5 * e[0]);
}

TEST_CASE("a residual correction that grows the residual is reported, not applied on", "[eigenfactor][refine][failure]") {
  // One eigenvalue of H's Lambda at a third of A's: I - H A has the eigenvalue
  // 1 - 3 = -2 there, so each residual is twice the last along it (r^T H r
  // four times). Along B = that eigenvector a single correction already grows it.
  std::mt19937 rng(8);
  const Eigen::MatrixXd A = randomSpd(rng);
  const Eigen::VectorXd B = Eigen::VectorXd::Ones(N);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  const RowMatrix C = es.eigenvectors().transpose();
  Eigen::VectorXd lambda = es.eigenvalues();
  lambda[0] /= 3;
  const auto applyH = [&](const Eigen::VectorXd& b, Eigen::Ref<Eigen::VectorXd> out) {
    out = C.transpose() * (lambda.cwiseInverse().asDiagonal() * (C * b));
  };
  Eigen::VectorXd u(N), r(N), du(N);
  for (int steps : {1, 2, 3}) {  // the residual after the last correction is measured too
    applyH(B, u);
    CHECK_FALSE(refineResidual(A, B, steps, applyH, u, r, du));
  }
  const Eigen::VectorXd along = C.row(0).transpose();
  applyH(along, u);
  CHECK_FALSE(refineResidual(A, along, 1, applyH, u, r, du));
  const Eigen::VectorXd across = C.row(1).transpose();  // where H A = I: one correction is exact
  applyH(across, u);
  CHECK(refineResidual(A, across, 1, applyH, u, r, du));
  CHECK_FALSE(refineDivergedCause(3).empty());
}

TEST_CASE("a residual correction that contracts is not stopped when the residual's 2-norm grows on the way", "[closedform][eigenfactor][refine]") {
  // A = diag(1, 1e6), H = A^-1 + e [[0, 1], [1, 0]] (positive definite for
  // e = 1e-4): I - A H = -A E has eigenvalues +-1e3 e = +-0.1, so u' converges
  // tenfold per correction, yet from B = (1, 0) the residual's 2-norm goes
  // 100, 0.01, 1: it grows a hundredfold at the second correction. In the
  // H-norm, which refineResidual watches, it shrinks tenfold every time, and
  // so does the error of u' in the A-norm (its 2-norm swings: 1e-4, 1e-2, 1e-6, 1e-4).
  constexpr double e = 1e-4;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2, 2), H(2, 2);
  A(0, 0) = 1, A(1, 1) = 1e6;
  H << 1, e, e, 1e-6;
  const Eigen::VectorXd B = Eigen::Vector2d(1, 0), exact = A.inverse() * B;
  const auto applyH = [&](const Eigen::VectorXd& b, Eigen::Ref<Eigen::VectorXd> out) { out = H * b; };
  Eigen::VectorXd u(2), r(2), du(2);
  const auto errorA = [&](const Eigen::VectorXd& v) { return std::sqrt((v - exact).dot(A * (v - exact))); };
  u = H * B;
  const double e0 = errorA(u);
  REQUIRE(refineResidual(A, B, 3, applyH, u, r, du));
  CHECK(errorA(u) == Approx(1e-3 * e0).epsilon(1e-6));  // 0.1 per correction, exactly
}
