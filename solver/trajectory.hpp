#pragma once
/// The trajectory type shared by the in-house methods and the Simbody
/// reference: samples on an output grid, in the source's order, with the
/// RunSpec that made it. appendSample is the one sampler of both engines.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "solver/model.hpp"
#include "solver/limits.hpp"
#include "solver/run_spec.hpp"

namespace em {

/// Pose of one body: CM position and orientation quaternion [w,x,y,z], world frame.
struct Pose {
  Vec3 p = Vec3::Zero();
  Vec4 quat = Vec4(1, 0, 0, 0);
};

/// Energies at one sample: E = T + V, T, and the work W_diss the dampers have
/// dissipated since t = 0 (0 without dampers); E + W_diss is conserved.
struct EnergySample {
  double total = 0, kinetic = 0, dissipated = 0;
};

/// Eigenfactor drift at one sample (NaN when the method has none).
struct SampleDiagnostics {
  double orth_err, offdiag_rel, min_gap, max_Omega, inv_err;
};

/// A mechanism's closures at one sample (docs/theory.md §15): the violation
/// (largest |g| over the point rows, m, and the turn of the direction rows,
/// rad; largest |G u|, m/s and rad/s) and the multipliers lambda of eq. (M7)
/// at the sampled state (alpha = beta = 0; NaN where A is not positive
/// definite there), one per closure row.
struct LoopSample {
  double position_m, position_rad, velocity_m, velocity_rad;
  Eigen::VectorXd lambda;
};

/// Counters of the eigenfactor methods over a whole run.
struct EigenStats {
  long jacobi_sweeps = 0, jacobi_rotations = 0;
  long jacobi_single_sweep_steps = 0;  ///< accepted steps that needed at most one sweep
  int jacobi_max_sweeps = 0;           ///< most sweeps in one step
  double max_abs_Omega = 0;            ///< over every right-hand-side evaluation
  double min_gap = 0, min_gap_time = 0;  ///< smallest eigenvalue gap over accepted steps, and when
  long block_merges = 0, block_splits = 0;  ///< eigen-block: clusters joined and broken up
};

/// What keeping a mechanism's loops closed took and left over a run, at its
/// accepted steps and output samples (docs/theory.md §15): the largest
/// violations, the rank of G A^-1 G^T (of G for ida), and the projections.
struct LoopStats {
  double position_m = 0, position_rad = 0;  ///< largest |g| over the point rows (m) and the axis rows (rad)
  double velocity_m = 0, velocity_rad = 0;  ///< largest |G u|, m/s and rad/s
  int rank_min = -1, rank_max = -1;         ///< over the evaluations (-1: none)
  long projections = 0, projection_iterations = 0;
  long projections_unconverged = 0;  ///< projections that stopped at the iteration bound above projection_tol (singular positions)
  /// Coordinate partitioning and the augmented Lagrangian: Newton solves (one
  /// per evaluation or step), their iterations, those that stopped at the bound
  /// above projection_tol.
  long newton_solves = 0, newton_iterations = 0, newton_unconverged = 0;
  /// The augmented Lagrangian: steps whose Newton stopped at round-off (its step no longer shrinking, within
  /// kNewtonRoundoff of its tolerance) rather than at the tolerance itself.
  long newton_at_roundoff = 0;
  long repartitions = 0;                   ///< coordinate partitioning: partitions chosen anew after the first
  std::vector<double> repartition_times;   ///< when (s): the first kRepartitionTimesKept of them
  /// Where the multipliers' rank fell below the rank of the first evaluation
  /// (a singular position: docs/theory.md §15), once per pass (falls within
  /// 1 ms of the last are one; the evaluations' times, trial stages
  /// included): the first kRepartitionTimesKept of them.
  std::vector<double> rank_drop_times;
  int rank_start = -1;      ///< the first evaluation's rank (-1: none)
  bool rank_below = false;  ///< the last evaluation's rank was below rank_start
};
inline constexpr size_t kRepartitionTimesKept = 20;

/// How a run ended and what it cost: one struct that a trajectory, its
/// metrics (compare/metrics.hpp) and the gallery's entry (extreme/) share,
/// assigned whole instead of copied field by field.
struct RunEnd {
  std::string failure;                     ///< cause when failed
  Failure failure_kind = Failure::None;    ///< its kind (registry's failure table)
  double failure_time = 0;                 ///< s; meaningful when failed()
  /// cond(A) = max/min eigenvalue of A at the state where the run stopped
  /// (in-house methods; NaN when it completed or for another engine).
  double failure_cond_A = std::numeric_limits<double>::quiet_NaN();
  double run_time_s = 0;                   ///< CPU time of the integration (sampling excluded)
  long steps = 0, rhs_evals = 0;
  long step_retries = 0;  ///< adaptive steps retried smaller after a failed trial stage
  /// Adaptive steps the output grid cut short: the step the controller asked
  /// for reached past the next output time, so it ended there. When every step
  /// is so cut, the grid, not the tolerance, set the steps (looser tolerances
  /// give the same run; GSL's steppers have no dense output to sample by).
  long grid_cut_steps = 0;
  bool has_loops = false;  ///< a mechanism's run: `loops` says how closed it stayed
  LoopStats loops;

  bool failed() const { return failure_kind != Failure::None; }
  /// Ok or Failed (outcomeName writes it).
  Outcome status() const { return failed() ? Outcome::Failed : Outcome::Ok; }
  /// The failure time, or nothing for a run that completed.
  std::optional<double> failedAt() const { return failed() ? std::optional<double>(failure_time) : std::nullopt; }
};

/// A sampled run. Coordinates, speeds and bodies in the source's order.
struct Trajectory : RunEnd {
  std::string scene;
  RunSpec run;                             ///< what made it
  std::vector<std::string> q_names, u_names, body_names;
  std::vector<int> angle_coords;           ///< indices into q that are angles (Model::angleCoordinates)
  std::vector<double> t;                   ///< sample times
  std::vector<Eigen::VectorXd> q, u;       ///< (nq), (nu) per sample
  std::vector<double> energy;              ///< total energy per sample
  std::vector<double> kinetic;             ///< kinetic energy per sample
  std::vector<double> dissipated;          ///< W_diss per sample (0 without dampers)
  std::vector<std::vector<Pose>> poses;    ///< per sample, per body
  std::vector<SampleDiagnostics> diag;     ///< per sample (eigenfactor methods), else empty
  std::vector<LoopSample> loop_samples;    ///< per sample on a model with loops (recordLoopSamples), else empty
  std::vector<std::string> lambda_names;   ///< "lambda.<loop>.<row>", one per closure row, with loop_samples
  std::vector<Impact> impacts;             ///< joint limits: the first kImpactsKept impacts (solver/limits.hpp)
  long impact_count = 0;                   ///< all of them
  std::vector<LimitedCoordinate> stops;    ///< the scene's joint limits (Model::limited), for the outputs and figures
  // Run summary: how it ended and its cost are RunEnd's.
  /// The largest distance (m) between a joint's two points over the steps:
  /// a maximal-coordinate engine's constraint violation (ODE); NaN otherwise.
  double max_joint_separation = std::numeric_limits<double>::quiet_NaN();
  double sample_time_s = 0;                ///< CPU time spent recording samples
  EigenStats eigen;  ///< eigenfactor methods only

  size_t size() const { return t.size(); }
  std::string method() const { return methodName(run.method); }
  std::string integrator() const { return integratorName(run.integrator); }
};

/// The steps the output grid cut short (RunEnd::grid_cut_steps) of a run made
/// with `spec`: counted for the in-house adaptive GSL steppers only (rk8pd,
/// rkf45, bsimp), nothing for other schemes.
std::optional<long> gridCutSteps(const RunEnd& r, const RunSpec& spec);
/// "98 of its 102 steps ended on the 0.01-s output grid: the grid, not the
/// tolerance, set them" where nine in ten steps of such a run were cut short, else "".
std::string gridSetStepsNote(const RunEnd& r, const RunSpec& spec);

/// Empty trajectory of `run` on `m`, with names taken from the model.
Trajectory makeTrajectory(const Model& m, const RunSpec& run);

/// Record the sample at time t: q (nq), u (nu) and poses (n) in the model's
/// internal order, stored in the source's order.
void appendSample(Trajectory& tr, const Model& m, double t, const double* q, const double* u,
                  const std::vector<Pose>& poses, const EnergySample& energy);

struct Workspace;
/// Record the sample at t from (q, u) alone (internal order), its poses and
/// energies by the in-house kinematics (formKinematics, formEnergies) in
/// `ws`, W_diss as given: for runs made elsewhere (a recorded run's samples).
void appendStateSample(Trajectory& tr, const Model& m, Workspace& ws, double t, const double* q, const double* u,
                       double dissipated);

/// Mark the run failed at t with its kind and cause (the first failure is kept).
void markFailed(Trajectory& tr, double t, Failure kind, const std::string& cause);

}  // namespace em
