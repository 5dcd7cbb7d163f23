#pragma once
/// The Junkins–Schaub eigenfactor pieces (paper §2, eqs. (5)–(17); docs/theory.md §7):
/// the cyclic Jacobi re-diagonalization, symmetric re-orthonormalization and the
/// drift diagnostics. Hand-written: they are the subject of the research.
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/Dense>

namespace em {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Off-diagonal Frobenius norm of a square matrix.
double offDiagonalNorm(const Eigen::Ref<const Eigen::MatrixXd>& X);

/// Outcome of eigenRates: ok, or the pair whose eigenvalue gap fell below the floor.
struct RateStatus {
  bool ok = true;
  int i = -1, j = -1;
  double gap = 0;
  double max_Omega = 0;  ///< max |Omega_ij| (when ok)
};

/// Junkins–Schaub rates (paper eqs. (8), (11), (14), (15); docs/theory.md §7):
/// G = C A' C^T, lambda' = diag G, Omega_ij = G_ij / (lambda_j - lambda_i),
/// C' = -Omega C. G is formed in `Omega` and left there as Omega; `AdotCt`
/// is scratch for A' C^T. Stops with !ok when a gap |lambda_j - lambda_i| is
/// below gap_floor.  // all (N x N) or (N)
RateStatus eigenRates(const Eigen::Ref<const RowMatrix>& C, const Eigen::Ref<const Eigen::VectorXd>& lambda,
                      const Eigen::MatrixXd& Adot, double gap_floor, Eigen::MatrixXd& Omega, Eigen::MatrixXd& AdotCt,
                      Eigen::Ref<Eigen::VectorXd> lambda_dot, Eigen::Ref<RowMatrix> Cdot);

/// Statistics of one Jacobi correction.
struct JacobiStats {
  int sweeps = 0;
  int rotations = 0;
  bool converged = true;
};

/// Preallocated scratch of the corrections (no allocation per step).
struct CorrectionScratch {
  explicit CorrectionScratch(int N) : work(N, N), W(N, N), es(N) {}
  Eigen::MatrixXd work, W;  // (N x N) products: C A C^T in the Jacobi correction, C C^T in the orthonormalization
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es;
};

/// One plane rotation zeroing X(p,q) of the symmetric X: X <- J^T X J, C <- J^T C
/// with J = [[c, s], [-s, c]] in the (p,q) plane (Golub & Van Loan, Alg. 8.4.1).  // X, C: (N x N)
void rotate(Eigen::MatrixXd& X, Eigen::Ref<RowMatrix> C, int p, int q);

/// Cyclic Jacobi on C A C^T warm-started from C (docs/theory.md §7, eq. (J)): rotate C <- R C until
/// off(C A C^T) <= tol * ||A||_F, then lambda = diag(C A C^T).  // A, C: (N x N)
JacobiStats jacobiCorrect(const Eigen::MatrixXd& A, Eigen::Ref<RowMatrix> C,
                          Eigen::Ref<Eigen::VectorXd> lambda, CorrectionScratch& w,
                          double tol, int max_sweeps);

/// C <- (C C^T)^(-1/2) C: the nearest orthogonal matrix (symmetric
/// orthonormalization, Löwdin).  // C: (N x N)
void symmetricOrthonormalize(Eigen::Ref<RowMatrix> C, CorrectionScratch& w);

/// Drift of the parameterization against a fresh factorization of A.
struct EigenDiagnostics {
  double orth_err = 0;     ///< ||C C^T - I||_F
  double offdiag_rel = 0;  ///< off(C A C^T) / ||A||_F
  double min_gap = 0;      ///< min over i<j of |lambda_i - lambda_j|
  double max_Omega = 0;    ///< max |Omega_ij| at this state
  double inv_err = 0;      ///< ||C^T Lambda^-1 C - A^-1||_F / ||A^-1||_F
};

/// Diagnostics of (C, lambda) against A (not on the hot path: allocates).
EigenDiagnostics eigenDiagnostics(const Eigen::MatrixXd& A, const Eigen::Ref<const RowMatrix>& C,
                                  const Eigen::Ref<const Eigen::VectorXd>& lambda, double max_Omega);

/// Residual correction (docs/theory.md §8, "Residual correction"): `steps`
/// times u' <- u' + H (B - A u'), H = C^T Lambda^-1 C (eigen-block: C^T D^-1 C)
/// the eigenfactors' approximate inverse of A, applied as applyH(b, out). Each
/// correction multiplies the error of u' by I - H A, so the factorization's
/// drift enters u' to the power steps + 1, and A is never factorized.
/// The residuals r_k = B - A u'_k obey r_k+1 = (I - A H) r_k, which shrinks
/// in the H-norm (r^T H r = r . du, free) exactly when every eigenvalue of
/// H A lies in (0, 2), while the 2-norm may grow on the way when A is ill
/// conditioned. The residual is measured before every correction and once
/// after the last (one more product A u' and application of H), so that a
/// single correction is judged too. Returns false when a correction did not
/// shrink r^T H r (or it went negative: H not positive definite), beyond
/// rounding (eps of (|A u'| + |B|) |u'|): H no longer contracts and u' is not
/// to be trusted. r, du: (N) scratch. `residual`, when given, gets the
/// relative residual after the last correction in the same norm,
/// sqrt(r^T H r / B^T H B) (udot = H B on entry; eq. (R') of docs/theory.md §8).
template <class ApplyH>
bool refineResidual(const Eigen::MatrixXd& A, const Eigen::VectorXd& B, int steps, ApplyH&& applyH,
                    Eigen::Ref<Eigen::VectorXd> udot, Eigen::VectorXd& r, Eigen::VectorXd& du, double* residual = nullptr) {
  constexpr double kRounding = std::numeric_limits<double>::epsilon();
  const double bHb = B.dot(udot);
  if (residual) *residual = 0;
  double previous = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= steps && steps > 0; ++k) {
    r.noalias() = A * udot;
    const double floor = kRounding * (r.norm() + B.norm()) * udot.norm();
    r = B - r;
    applyH(r, du);
    const double rHr = r.dot(du);
    if ((!(rHr < previous) || rHr < 0) && std::abs(rHr) > floor) return false;
    previous = rHr;
    if (k < steps) udot += du;  // after the last correction the residual is only measured
  }
  if (residual && steps > 0)
    *residual = previous <= 0 ? 0.0 : bHb > 0 ? std::sqrt(previous / bHb) : std::numeric_limits<double>::infinity();
  return true;
}

/// The failure's cause when refineResidual returns false.
std::string refineDivergedCause(int steps);
/// The failure's cause when the last correction left the relative residual above the tolerance.
std::string refineNotConvergedCause(int steps, double residual, double tol);

/// min over i<j of |lambda_i - lambda_j| (+inf for N < 2).
double minEigenGap(const Eigen::Ref<const Eigen::VectorXd>& lambda);

}  // namespace em
