// The formulations' table and what they share: the multipliers of eq. (M7)
// (docs/theory.md §15). Each formulation's own code is in its file,
// solver/mechanism/formulations/.
#include "solver/mechanism/formulation.hpp"

#include <algorithm>
#include <cmath>

namespace em {

namespace {

const std::vector<FormulationInfo>& table() {
  static const std::vector<FormulationInfo> rows = {
      {Formulation::Baumgarte, "baumgarte",
       "Lagrange multipliers at acceleration level, Baumgarte's alpha and beta (default 0: the raw drift)", false, false,
       Integrator::RK4, makeMultipliers, nullptr},
      {Formulation::Projection, "projection",
       "the same, then after every accepted step q onto g = 0 (Gauss-Newton in A's metric) and u onto G u = 0", true, false,
       Integrator::RK4, makeProjection, projectionFigures},
      {Formulation::UdwadiaKalaba, "udwadia-kalaba",
       "u' = a + M (G M)^+ (b - G a) with M M^T = A^-1 from the method's own factors (eigenfactors: M = C^T Lambda^(-1/2)), "
       "Baumgarte's b, no projection",
       false, false, Integrator::RK4, makeUdwadiaKalaba, nullptr},
      {Formulation::CoordinatePartitioning, "coordinate-partitioning",
       "Wehage-Haug: the independent coordinates integrated, the dependent ones by Newton on g = 0 at every evaluation; "
       "re-partitioned where the pivots degrade tenfold",
       true, false, Integrator::RK4, makeCoordinatePartitioning, partitioningFigures},
      // Its own integrator steps A, B and the loops itself (solver/augmented_lagrangian.cpp); an
      // evaluation of u' at a sample takes the multipliers.
      {Formulation::AugmentedLagrangian, "augmented-lagrangian",
       "index-3 augmented Lagrangian with mass-orthogonal projections (Bayo, Garcia de Jalon: ALI3-P), under its own "
       "integrator trapezoidal (fixed step dt)",
       false, true, Integrator::Trapezoidal, makeMultipliers, augmentedLagrangianFigures}};
  return rows;
}

constexpr bool rowsInOrder(std::initializer_list<Formulation> ids) {
  int k = 0;
  for (Formulation f : ids)
    if (static_cast<int>(f) != k++) return false;
  return true;
}
static_assert(rowsInOrder({Formulation::Baumgarte, Formulation::Projection, Formulation::UdwadiaKalaba,
                           Formulation::CoordinatePartitioning, Formulation::AugmentedLagrangian}),
              "formulationTable: one row per Formulation, in its order (formulationRow indexes by it)");

}  // namespace

const std::vector<FormulationInfo>& formulationTable() { return table(); }

const FormulationInfo& formulationRow(Formulation f) { return table().at(static_cast<size_t>(f)); }

const char* formulationName(Formulation f) { return formulationRow(f).name; }

bool findFormulation(const std::string& name, Formulation& out) {
  for (const FormulationInfo& r : table())
    if (name == r.name) {
      out = r.id;
      return true;
    }
  return false;
}

const FormulationInfo* formulationBringing(Integrator i) {
  for (const FormulationInfo& r : table())
    if (r.brings_integrator && r.own_integrator == i) return &r;
  return nullptr;
}

void LoopFormulation::countRank(int rank, double t) {
  if (stats_.rank_start < 0) stats_.rank_start = rank;
  // A fall within 1 ms of the last one recorded is the same pass (the stages of
  // the steps around a singular position fall and rise several times there).
  constexpr double kSamePass = 1e-3;
  const bool below = rank < stats_.rank_start;
  const std::vector<double>& drops = stats_.rank_drop_times;
  if (below && !stats_.rank_below && drops.size() < kRepartitionTimesKept && (drops.empty() || std::abs(t - drops.back()) > kSamePass))
    stats_.rank_drop_times.push_back(t);
  stats_.rank_below = below;
  stats_.rank_min = stats_.rank_min < 0 ? rank : std::min(stats_.rank_min, rank);
  stats_.rank_max = std::max(stats_.rank_max, rank);
}

// u' = a + A^-1 G^T lambda (eq. (M7)), a the tree's u' in udot.
Status LoopFormulation::accelerations(double t, Workspace& ws, const double* y, const double* extra, MethodFactors& f,
                                      double* udot) {
  formLoops(m_, ws, y + m_.nq, loops_);
  Eigen::Map<Eigen::VectorXd> a(udot, m_.nu);
  if (const TreeCholesky* tree = f.treeFactor(extra)) {
    countRank(solve_.solve(loops_, *tree, o_.alpha, o_.beta, a), t);
    return {};
  }
  const Eigen::MatrixXd& AinvGt = f.inverseATimesGt(extra, loops_);
  if (!AinvGt.allFinite()) return f.solveFailed(t, "A^-1 G^T not finite (A not positive definite)");
  countRank(solve_.solve(loops_, AinvGt, o_.alpha, o_.beta, a), t);
  return {};
}

std::unique_ptr<LoopFormulation> makeMultipliers(const Model& m, const LoopOptions& o) {
  return std::make_unique<LoopFormulation>(m, o);
}

}  // namespace em
