// Udwadia-Kalaba (docs/theory.md eq. (M11)): u' = a + M (G M)^+ (b - G a),
// M M^T = A^-1 from the method's own factors, Baumgarte's b; no projection.
#include "solver/mechanism/formulation.hpp"

namespace em {

namespace {

class UdwadiaKalaba : public LoopFormulation {
 public:
  using LoopFormulation::LoopFormulation;

  Status accelerations(double t, Workspace& ws, const double* y, const double* extra, MethodFactors& f, double* udot) override {
    formLoops(m_, ws, y + m_.nq, loops_);
    const Eigen::MatrixXd& M = f.inverseSquareRoot(extra);
    if (!M.allFinite()) return f.solveFailed(t, "A^(-1/2) not finite (A not positive definite)");
    Eigen::Map<Eigen::VectorXd> a(udot, m_.nu);
    countRank(solve_.solveUdwadiaKalaba(loops_, M, o_.alpha, o_.beta, a), t);
    return {};
  }
};

}  // namespace

std::unique_ptr<LoopFormulation> makeUdwadiaKalaba(const Model& m, const LoopOptions& o) {
  return std::make_unique<UdwadiaKalaba>(m, o);
}

}  // namespace em
