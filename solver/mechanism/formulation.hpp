#pragma once
/// The formulations that keep a mechanism's loops closed (docs/theory.md §15):
/// each one object behind LoopFormulation, created from its row of
/// formulationTable() (one file each, solver/mechanism/formulations/). Its row
/// says what it is (whether it moves the state between steps, whether it
/// brings its own integrator, what it reports); Dynamics holds one and asks it
/// at every evaluation and after every step, never which one it is.
#include <memory>
#include <string>
#include <vector>

#include "solver/mechanism/projection.hpp"
#include "solver/method.hpp"

namespace em {

/// What a formulation takes from the method that forms u': A^-1 G^T and A^(-1/2)
/// from the method's own factors (Dynamics, eq. (M7) and (M11)).
class MethodFactors {
 public:
  virtual ~MethodFactors() = default;
  /// A^-1 G^T at the formed A, G = ls.G.  // extra: the method's extra state
  virtual const Eigen::MatrixXd& inverseATimesGt(const double* extra, const LoopState& ls) = 0;
  /// M with M M^T = A^-1 at the formed A.
  virtual const Eigen::MatrixXd& inverseSquareRoot(const double* extra) = 0;
  /// A's tree-sparse factors at the formed A where the method's A^-1 is A's
  /// own and the tree's pattern pays (docs/theory.md §16): the multipliers then
  /// cost O(rows x depth); nullptr: take inverseATimesGt.
  virtual const TreeCholesky* treeFactor(const double* extra) = 0;
  /// A non-finite A^-1 G^T or M as a failure at t: the method's own cause where it has one.
  virtual Status solveFailed(double t, const char* otherwise) const = 0;
};

/// One formulation on one model, its scratch and its counters (LoopStats).
class LoopFormulation {
 public:
  LoopFormulation(const Model& m, const LoopOptions& o) : m_(m), o_(o), loops_(m), solve_(m) {}
  virtual ~LoopFormulation() = default;
  /// The state the right-hand side is evaluated at: y itself, or (coordinate
  /// partitioning) y with its dependent coordinates solved from the
  /// independent ones, in scratch the formulation owns.  // y: (size)
  virtual Status evaluationState(double t, Workspace& ws, const double* y, int size, const double*& at) {
    (void)t, (void)ws, (void)size;
    at = y;
    return {};
  }
  /// u' closing the loops, the tree's a in udot on entry, the equations
  /// formed at y; the rank of the solve counted. By default the multipliers
  /// of eq. (M7) with Baumgarte's alpha and beta.  // y: q then u; udot: (nu)
  virtual Status accelerations(double t, Workspace& ws, const double* y, const double* extra, MethodFactors& f, double* udot);
  /// After an accepted step, before the loops are measured: onto the loops
  /// (projection, coordinate partitioning), or nothing.
  virtual Status afterStep(double t, Workspace& ws, double* y) {
    (void)t, (void)ws, (void)y;
    return {};
  }
  LoopState& loops() { return loops_; }
  LoopStats& stats() { return stats_; }
  const LoopStats& stats() const { return stats_; }

 protected:
  void countRank(int rank, double t);
  const Model& m_;
  const LoopOptions o_;
  LoopState loops_;
  ConstrainedSolve solve_;
  LoopStats stats_;
};

/// One figure a formulation's run reports beside the loops' violation (the
/// run's `loops` object: docs/report-format.md): its key, and an integer
/// count or a number.
struct FormulationFigure {
  const char* key;
  double value = 0;
  bool integer = false;
  const std::vector<double>* list = nullptr;  ///< a list instead (into the LoopStats the figures were read from)
};

/// One row per formulation (solver/method_options.hpp's Formulation), in its
/// order: its name (--formulation), what it does, whether it moves q and u
/// between steps (a multistep integrator's history cannot take that), the
/// integrator it brings (it runs under no other, and that integrator runs no
/// other formulation on a mechanism), how it is made, and what its run reports.
struct FormulationInfo {
  Formulation id;
  const char* name;
  const char* summary;
  bool corrects_state;
  bool brings_integrator;      ///< false: any integrator of ours but one another formulation brings
  Integrator own_integrator;   ///< the one it brings (read where brings_integrator)
  std::unique_ptr<LoopFormulation> (*make)(const Model& m, const LoopOptions& o);
  /// Its figures of a run whose counters are s and options o (appended to
  /// out), or nullptr: none beyond the loops' violation and Baumgarte's values.
  void (*figures)(const LoopStats& s, const LoopOptions& o, std::vector<FormulationFigure>& out);
};
const std::vector<FormulationInfo>& formulationTable();
const FormulationInfo& formulationRow(Formulation f);
const char* formulationName(Formulation f);
/// The formulation named `name`, or false.
bool findFormulation(const std::string& name, Formulation& out);
/// The formulation that brings integrator i, or nullptr.
const FormulationInfo* formulationBringing(Integrator i);

/// The rows' parts, written in each formulation's file (solver/mechanism/formulations/).
std::unique_ptr<LoopFormulation> makeMultipliers(const Model& m, const LoopOptions& o);
std::unique_ptr<LoopFormulation> makeProjection(const Model& m, const LoopOptions& o);
std::unique_ptr<LoopFormulation> makeUdwadiaKalaba(const Model& m, const LoopOptions& o);
std::unique_ptr<LoopFormulation> makeCoordinatePartitioning(const Model& m, const LoopOptions& o);
void projectionFigures(const LoopStats& s, const LoopOptions& o, std::vector<FormulationFigure>& out);
void partitioningFigures(const LoopStats& s, const LoopOptions& o, std::vector<FormulationFigure>& out);
void augmentedLagrangianFigures(const LoopStats& s, const LoopOptions& o, std::vector<FormulationFigure>& out);

}  // namespace em
