#include "solver/trajectory.hpp"

#include "solver/formation.hpp"
#include "solver/text.hpp"

namespace em {

Trajectory makeTrajectory(const Model& m, const RunSpec& run) {
  Trajectory tr;
  tr.scene = m.name;
  tr.run = run;
  tr.q_names = m.qNames();
  tr.u_names = m.uNames();
  tr.angle_coords = m.angleCoordinates();
  tr.body_names.resize(m.n());
  for (const Body& b : m.bodies) tr.body_names[b.file_index] = b.name;
  tr.stops = m.limited;
  return tr;
}

void appendSample(Trajectory& tr, const Model& m, double t, const double* q, const double* u,
                  const std::vector<Pose>& poses, const EnergySample& energy) {
  Eigen::VectorXd qf, uf;
  m.qToFile(Eigen::Map<const Eigen::VectorXd>(q, m.nq), qf);
  m.uToFile(Eigen::Map<const Eigen::VectorXd>(u, m.nu), uf);
  std::vector<Pose> pf(m.n());
  for (int i = 0; i < m.n(); ++i) pf[m.bodies[i].file_index] = poses[i];
  tr.t.push_back(t);
  tr.q.push_back(std::move(qf));
  tr.u.push_back(std::move(uf));
  tr.energy.push_back(energy.total);
  tr.kinetic.push_back(energy.kinetic);
  tr.dissipated.push_back(energy.dissipated);
  tr.poses.push_back(std::move(pf));
}

void appendStateSample(Trajectory& tr, const Model& m, Workspace& ws, double t, const double* q, const double* u,
                       double dissipated) {
  formKinematics(m, q, u, ws);
  formEnergies(m, q, ws);
  std::vector<Pose> poses(m.n());
  for (int i = 0; i < m.n(); ++i) poses[i] = {ws.r[i], matrixToQuat(ws.R[i])};
  appendSample(tr, m, t, q, u, poses, {ws.energy(), ws.kinetic, dissipated});
}

void markFailed(Trajectory& tr, double t, Failure kind, const std::string& cause) {
  if (tr.failed()) return;
  tr.failure = cause;
  tr.failure_kind = kind == Failure::None ? Failure::Engine : kind;  // a failure always has a kind
  tr.failure_time = t;
}

std::optional<long> gridCutSteps(const RunEnd& r, const RunSpec& spec) {
  if (spec.engine() != Engine::InHouse || spec.fixedStep() || !info(spec.integrator).gsl) return std::nullopt;
  return r.grid_cut_steps;
}

std::string gridSetStepsNote(const RunEnd& r, const RunSpec& spec) {
  const std::optional<long> cut = gridCutSteps(r, spec);
  // The first steps grow from the controller's start before the grid cuts them: nine in ten is the grid's run.
  if (!cut || r.steps == 0 || 10 * *cut < 9 * r.steps) return "";
  return std::to_string(*cut) + " of its " + std::to_string(r.steps) + " steps ended on the " + gnum(spec.output_dt) +
         "-s output grid: the grid, not the tolerance " + gnum(spec.tol) + ", set them";
}

}  // namespace em
