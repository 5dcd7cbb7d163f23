#include "solver/formulation.hpp"

namespace em {

Status Formulation::afterStep(double, const Workspace&, double*, StepInfo&) { return {}; }

EigenDiagnostics Formulation::diagnostics(const Workspace&, const double*, double) const { return {}; }

}  // namespace em
