// The projection (docs/theory.md eqs. (M7)-(M9)), the default: the
// multipliers at every evaluation, then after every accepted step q onto
// g(q) = 0 by Gauss-Newton in A's metric and u onto G u = 0.
#include "solver/mechanism/formulation.hpp"

namespace em {

namespace {

class Projection : public LoopFormulation {
 public:
  Projection(const Model& m, const LoopOptions& o) : LoopFormulation(m, o), project_(m) {}

  Status afterStep(double t, Workspace& ws, double* y) override {
    ++stats_.projections;
    const LoopProjector::Result r = project_.positions(m_, ws, y, y + m_.nq, o_.projection_tol, o_.projection_iterations);
    stats_.projection_iterations += r.iterations;
    if (!r.finite) return Status::failure(t, Failure::NonFinite, "the projection met a non-finite loop gap");
    // Near a singular position Gauss-Newton converges slowly: the step goes on
    // unconverged, counted, and fails only where the gap passes loop_tol (Dynamics::afterStep).
    if (!r.converged) ++stats_.projections_unconverged;
    project_.velocities(y + m_.nq);
    return {};
  }

 private:
  LoopProjector project_;
};

}  // namespace

std::unique_ptr<LoopFormulation> makeProjection(const Model& m, const LoopOptions& o) { return std::make_unique<Projection>(m, o); }

void projectionFigures(const LoopStats& s, const LoopOptions& o, std::vector<FormulationFigure>& out) {
  out.push_back({"projections", double(s.projections), true});
  out.push_back({"projection_iterations", double(s.projection_iterations), true});
  out.push_back({"projections_unconverged", double(s.projections_unconverged), true});
  out.push_back({"projection_tol", o.projection_tol});
}

}  // namespace em
