#pragma once
/// The closures at one state (docs/theory.md §15, eqs. (M1)-(M4b)): g(q), its
/// Jacobian G (in u, so that g' = G u) and the velocity-product part c of g''
/// (g'' = G u' + c), every loop's rows formed by its kind
/// (solver/mechanism/kinds/<kind>.cpp, selected by model.hpp's kLoopTypes), and
/// the violation a report calls the loops' figures.
#include <string>

#include "solver/trajectory.hpp"
#include "solver/workspace.hpp"

namespace em {

/// The closures at one state: g (m), G (m x nu), G u, and c = G' u, so that
/// g'' = G u' + c (theory.md eqs. (M1)-(M4)); m = Model::loop_rows.
struct LoopState {
  explicit LoopState(const Model& m);
  Eigen::VectorXd g, Gu, c;
  Eigen::MatrixXd G;
  Eigen::Matrix3Xd Jw;  ///< scratch of the kinds' rows: an angular Jacobian (3 x nu)
  /// Per loop, how far its directions are turned from where the closure holds
  /// them (rad; 0 for a ball): a hinge's angle between axis_a and axis_b, a
  /// universal's departure from square, a weld's or a slider's angle of R_b
  /// against R_a rel (eq. (M4b)). The direction rows g vanish also at turns
  /// that are not the closure's (a weld's frame turned 120 degrees about its
  /// diagonal, a hinge's axes opposed); this does not.
  std::vector<double> turn;
  /// The largest |g| over the point rows (m), the largest turn (rad), and the
  /// largest |G u| over the point and the direction rows (m/s, rad/s): what a
  /// report calls the violation.
  double position_m = 0, position_rad = 0, velocity_m = 0, velocity_rad = 0;
};

/// What a kind's rows read: the model, the formed kinematics, the speeds and the loop.
struct LoopContext {
  const Model& m;
  const Workspace& ws;
  const double* u;  // (nu)
  const Loop& loop;
  const std::vector<int>& speeds;  ///< the loop's (Model::loop_speeds): its rows' only nonzero columns
};

/// A closure kind's equations (one file each, solver/mechanism/kinds/): rows
/// r .. r + equations - 1 of ls.g, ls.G and ls.c, its point rows (m) first;
/// returns the loop's turn (eq. (M4b); 0 where it holds no direction).
struct LoopEquations {
  double (*form)(const LoopContext& x, int r, LoopState& ls);
  /// How far its points are apart where the closure holds them together (m):
  /// given a's point xa, b's point xb and R_a in the world (an engine's
  /// bodies, read back from its own state).
  double (*gap)(const Loop& l, const Vec3& xa, const Vec3& xb, const Mat3& Ra);
};
/// The points' gap of the kind whose loop `l` is (its LoopEquations::gap).
double loopPointGap(const Loop& l, const Vec3& xa, const Vec3& xb, const Mat3& Ra);

/// g, G, G u and c at the formed kinematics.  // u: (nu)
void formLoops(const Model& m, const Workspace& ws, const double* u, LoopState& ls);

/// M += scale * G^T G, summed loop by loop over its rows and its speeds
/// (Model::loop_speeds): G's other columns are zero, so this is all of G^T G
/// at O(rows x speeds per loop), not O(rows x nu^2) (the augmented
/// Lagrangian's penalty term, docs/theory.md eq. (M13)).  // M: (nu x nu)
void addLoopGramian(const Model& m, const Eigen::MatrixXd& G, double scale, Eigen::MatrixXd& M);

/// s's largest violations grow by ls's (what a report calls the violation).
void recordViolation(const LoopState& ls, LoopStats& s);

/// The loops' violation at a state another engine reached (its samples), by
/// our g(q) and G u: LoopStats' largest values grow; rank is not touched.
class LoopMeter {
 public:
  explicit LoopMeter(const Model& m) : m_(m), ws_(m), loops_(m) {}
  void record(const double* q, const double* u, LoopStats& s);  // q: (nq), u: (nu)

 private:
  const Model& m_;
  Workspace ws_;
  LoopState loops_;
};

/// The first closure a state leaves open by more than `tol` (m or rad, m/s or
/// rad/s): its index in Model::loops and "loop 'name' is open by 3.2e-4 m"
/// (or "... separates at 2e-3 m/s"); index -1 when every loop is closed.
struct LoopGap {
  int loop = -1;
  std::string what;
};
LoopGap openLoop(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u, double tol);

}  // namespace em
