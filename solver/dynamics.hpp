#pragma once
/// One method's dynamics on one model (docs/theory.md §7–8): the state
/// layout, the right-hand side and what follows an accepted step. It holds no
/// run state: an evaluation returns its status, and the integration loop owns
/// the counters and the failure (solver/integrate.cpp).
/// State y = [q (nq), u (nu), the method's extra state (its row's ExtraState:
/// C and lambda, or C and D), then, when the model has dampers, the
/// dissipated work W_diss (1), with W_diss' = sum c u^2].
#include <memory>

#include "solver/control.hpp"
#include "solver/mechanism/formulation.hpp"
#include "solver/trajectory.hpp"
#include "solver/method.hpp"

namespace em {

class Dynamics {
 public:
  /// Throws std::invalid_argument for a method another engine runs.
  Dynamics(const Model& m, Method method, const MethodOptions& opt = {});
  /// Built in place: factors_ refers to this object (neither copied nor moved).
  Dynamics(const Dynamics&) = delete;
  Dynamics& operator=(const Dynamics&) = delete;

  const Model& model() const { return model_; }
  Method method() const { return method_; }
  /// Whether the method carries eigenfactor drift diagnostics.
  bool eigenfactor() const { return f_->hasDiagnostics(); }
  /// Whether a step's state is changed after it: the method's correction, or
  /// a formulation that moves q and u onto the loops (its row's corrects_state).
  bool correctsAfterStep() const { return f_->correctsAfterStep() || (form_ && formulationRow(opt_.loops.formulation).corrects_state); }
  const LoopStats& loopStats() const { return form_ ? form_->stats() : no_loops_; }
  /// Form the loops at y and count their violation in loopStats() (an output sample).
  void recordLoopsAt(const double* y);
  /// A failure (loops-open, at t) where the loops last formed are open beyond
  /// the loop tolerance (m or rad), else ok: every run's check, IDA's at its samples.
  Status loopsOpen(double t) const;
  int size() const { return size_; }
  /// Where the extra state starts in y (laid out as info(method()).extra says).
  int offsetExtra() const { return model_.nq + model_.nu; }
  /// Index of W_diss in y, or -1 without dampers.
  int offsetDissipated() const { return model_.has_dampers ? size_ - 1 : -1; }
  /// W_diss at y (0 without dampers).
  double dissipated(const double* y) const { return model_.has_dampers ? y[size_ - 1] : 0.0; }

  /// y0 from (q, u) (internal order) and the method's extra state at A(q).
  Eigen::VectorXd initialState(const Eigen::VectorXd& q, const Eigen::VectorXd& u);
  /// dy/dt at (t, y); `info` (may be null) receives what the evaluation measured.
  Status rhs(double t, const double* y, double* dydt, EvalInfo* info = nullptr);
  /// After every accepted step: normalize quaternions, check for blow-up,
  /// apply the method's correction.
  Status afterStep(double t, double* y, StepInfo& info);
  /// Form the kinematics and energies at y into the workspace (for output samples).
  void kinematicsAt(const double* y);
  /// cond(A) at y's q (conditionNumber; allocates: for the report of a failure).
  double conditionAt(const double* y);
  /// Eigenfactor drift diagnostics at y (eigenfactor methods; allocates nothing).
  EigenDiagnostics diagnosticsAt(const double* y);
  Workspace& workspace() { return ws_; }
  /// The joint controllers (theory.md §18): a sampled loop is sampled by the
  /// integration at its instants (sampleControl), a continuous one at every rhs.
  const ControlLoop& control() const { return control_; }
  void sampleControl(double t, const double* y) { control_.sample(t, y, y + model_.nq); }

 private:
  // A^-1 G^T and A^(-1/2) from the method's own factors, else a Cholesky of the formed A.
  class Factors : public MethodFactors {
   public:
    Factors(Dynamics& d) : d_(d) {}
    const Eigen::MatrixXd& inverseATimesGt(const double* extra, const LoopState& ls) override;
    const Eigen::MatrixXd& inverseSquareRoot(const double* extra) override;
    const TreeCholesky* treeFactor(const double* extra) override;
    Status solveFailed(double t, const char* otherwise) const override;

   private:
    Dynamics& d_;
  };
  void recordLoops();

  const Model& model_;
  Method method_;
  MethodOptions opt_;
  std::unique_ptr<MethodImpl> f_;
  int size_;
  Workspace ws_;
  ControlLoop control_;
  Eigen::VectorXd scratch_;  // (size) derivative scratch of diagnosticsAt
  // A mechanism's loops (docs/theory.md §15): its formulation (none on a model
  // without loops), and the method's factors it asks for, sized once.
  std::unique_ptr<LoopFormulation> form_;
  Factors factors_;
  LoopStats no_loops_;
  Eigen::MatrixXd Gt_, AinvGt_;  // (nu x m)
  Eigen::MatrixXd M_;            // (nu x nu): M M^T = A^-1 (Udwadia-Kalaba)
  Eigen::LLT<Eigen::MatrixXd> llt_;
  // A's tree-sparse factors for a method whose A^-1 is A's own but which has
  // none (articulated, eigen-block), where the pattern pays; else null.
  std::unique_ptr<TreeCholesky> tree_;
};

/// " (gimbal lock: body 'arm' q1 = 1.5708 rad)" for every gimbal whose middle
/// angle is within 1e-3 (in cos) of +-90 deg at q (internal order), else "".
std::string gimbalLockHint(const Model& m, const double* q);

}  // namespace em
