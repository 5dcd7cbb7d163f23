// Coordinate partitioning (Wehage and Haug; docs/theory.md eq. (M12)): the ODE
// is the independent coordinates'; at every evaluation the dependent ones
// follow by Newton on g(q) = 0, and after every accepted step the partition is
// kept while its pivots hold, chosen anew where they degrade, and the run
// fails at a singular position (which it cannot pass).
#include "solver/mechanism/formulation.hpp"

#include "solver/text.hpp"

namespace em {

namespace {

class CoordinatePartitioning : public LoopFormulation {
 public:
  CoordinatePartitioning(const Model& m, const LoopOptions& o) : LoopFormulation(m, o), partition_(m) {}

  Status evaluationState(double t, Workspace& ws, const double* y, int size, const double*& at) override {
    consistent_ = Eigen::Map<const Eigen::VectorXd>(y, size);  // sized once: no allocation after the first
    if (Status s = dependent(t, ws, consistent_.data(), false); !s) return s;
    at = consistent_.data();
    return {};
  }

  Status afterStep(double t, Workspace& ws, double* y) override { return dependent(t, ws, y, true); }

 private:
  // y's dependent coordinates from its independent ones (eq. (M12)), counted;
  // `accepted`: after a step, where the partition may change.
  Status dependent(double t, Workspace& ws, double* y, bool accepted) {
    if (!partition_.chosen()) {
      formKinematics(m_, y, y + m_.nq, ws);
      formLoops(m_, ws, y + m_.nq, loops_);
      partition_.choose(loops_);
    }
    ++stats_.newton_solves;
    const LoopProjector::Result r = partition_.dependent(m_, ws, loops_, y, y + m_.nq, o_.projection_tol, o_.projection_iterations);
    stats_.newton_iterations += r.iterations;
    if (!r.finite) return Status::failure(t, Failure::NonFinite, "coordinate partitioning's Newton met a non-finite loop gap");
    if (!r.converged) ++stats_.newton_unconverged;  // goes on, counted; fails only beyond loop_tol (Dynamics::afterStep)
    if (!accepted) return {};
    if (partition_.degraded(loops_)) {  // chosen anew at the accepted state, which is on the loops
      partition_.choose(loops_);
      ++stats_.repartitions;
      if (stats_.repartition_times.size() < kRepartitionTimesKept) stats_.repartition_times.push_back(t);
    }
    if (partition_.bestPivotRatio() < kSingularPivotRatio)
      return Status::failure(t, Failure::Singular,
                             "a singular position: the loops' Jacobian G is within " + gnum(partition_.bestPivotRatio(), 2) +
                                 " (its smallest pivot over its largest) of losing rank, which coordinate partitioning "
                                 "cannot pass (the projection formulation can)");
    return {};
  }

  CoordinatePartition partition_;
  Eigen::VectorXd consistent_;  // the evaluated state, its dependent coordinates solved
};

}  // namespace

std::unique_ptr<LoopFormulation> makeCoordinatePartitioning(const Model& m, const LoopOptions& o) {
  return std::make_unique<CoordinatePartitioning>(m, o);
}

void partitioningFigures(const LoopStats& s, const LoopOptions& o, std::vector<FormulationFigure>& out) {
  // Its Newton runs once per evaluation.
  out.push_back({"newton_solves", double(s.newton_solves), true});
  out.push_back({"newton_iterations", double(s.newton_iterations), true});
  out.push_back({"newton_unconverged", double(s.newton_unconverged), true});
  out.push_back({"newton_tol", o.projection_tol});
  out.push_back({"repartitions", double(s.repartitions), true});
  out.push_back({"repartition_times", 0, false, &s.repartition_times});  // the first kRepartitionTimesKept
}

}  // namespace em
