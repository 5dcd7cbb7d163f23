// The formulations' table (docs/theory.md §15).
#include "solver/mechanism/formulation.hpp"

namespace em {

const std::vector<FormulationInfo>& formulationTable() {
  static const std::vector<FormulationInfo> table = {
      {Formulation::Baumgarte, "baumgarte", "Lagrange multipliers at acceleration level, Baumgarte's alpha and beta (default 0: the raw drift)"},
      {Formulation::Projection, "projection", "the same, then after every accepted step q onto g = 0 (Gauss-Newton in A's metric) and u onto G u = 0"},
      {Formulation::UdwadiaKalaba, "udwadia-kalaba",
       "u' = a + M (G M)^+ (b - G a) with M M^T = A^-1 from the method's own factors (eigenfactors: M = C^T Lambda^(-1/2)), "
       "Baumgarte's b, no projection"},
      {Formulation::CoordinatePartitioning, "coordinate-partitioning",
       "Wehage-Haug: the independent coordinates integrated, the dependent ones by Newton on g = 0 at every evaluation; "
       "re-partitioned where the pivots degrade tenfold"},
      {Formulation::AugmentedLagrangian, "augmented-lagrangian",
       "index-3 augmented Lagrangian with mass-orthogonal projections (Bayo, Garcia de Jalon: ALI3-P), under its own "
       "integrator trapezoidal (fixed step dt)"}};
  return table;
}

const char* formulationName(Formulation f) {
  for (const FormulationInfo& r : formulationTable())
    if (r.id == f) return r.name;
  return "?";
}

bool findFormulation(const std::string& name, Formulation& out) {
  for (const FormulationInfo& r : formulationTable())
    if (name == r.name) {
      out = r.id;
      return true;
    }
  return false;
}

}  // namespace em
