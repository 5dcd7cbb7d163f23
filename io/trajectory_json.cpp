#include "io/trajectory_json.hpp"

#include <stdexcept>

namespace em {

using json = nlohmann::json;

namespace {

json vectorJson(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

Eigen::VectorXd vectorFrom(const json& j) {
  const std::vector<double> v = j.get<std::vector<double>>();
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// Per sample, per body: [x, y, z, qw, qx, qy, qz].
json posesJson(const std::vector<Pose>& poses) {
  json out = json::array();
  for (const Pose& p : poses) out.push_back({p.p.x(), p.p.y(), p.p.z(), p.quat[0], p.quat[1], p.quat[2], p.quat[3]});
  return out;
}

std::vector<Pose> posesFrom(const json& j) {
  std::vector<Pose> out;
  for (const json& b : j) {
    const std::vector<double> v = b.get<std::vector<double>>();
    if (v.size() != 7) throw std::invalid_argument("a pose has 7 numbers");
    Pose p;
    p.p = Vec3(v[0], v[1], v[2]);
    p.quat = Vec4(v[3], v[4], v[5], v[6]);
    out.push_back(p);
  }
  return out;
}

// LoopStats whole (a run in a child process carries how it kept its loops
// closed back to the parent); null for a run without loops.
json loopStatsJson(const Trajectory& tr) {
  if (!tr.has_loops) return nullptr;
  const LoopStats& l = tr.loops;
  return {{"position_m", l.position_m},           {"position_rad", l.position_rad},
          {"velocity_m", l.velocity_m},           {"velocity_rad", l.velocity_rad},
          {"rank_min", l.rank_min},               {"rank_max", l.rank_max},
          {"projections", l.projections},         {"projection_iterations", l.projection_iterations},
          {"projections_unconverged", l.projections_unconverged},
          {"newton_solves", l.newton_solves},     {"newton_iterations", l.newton_iterations},
          {"newton_unconverged", l.newton_unconverged},
          {"repartitions", l.repartitions},       {"repartition_times", l.repartition_times}};
}

void loopStatsFrom(const json& j, Trajectory& tr) {
  tr.has_loops = !j.is_null();
  if (!tr.has_loops) return;
  LoopStats& l = tr.loops;
  l.position_m = j.at("position_m").get<double>(), l.position_rad = j.at("position_rad").get<double>();
  l.velocity_m = j.at("velocity_m").get<double>(), l.velocity_rad = j.at("velocity_rad").get<double>();
  l.rank_min = j.at("rank_min").get<int>(), l.rank_max = j.at("rank_max").get<int>();
  l.projections = j.at("projections").get<long>(), l.projection_iterations = j.at("projection_iterations").get<long>();
  l.projections_unconverged = j.at("projections_unconverged").get<long>();
  l.newton_solves = j.at("newton_solves").get<long>(), l.newton_iterations = j.at("newton_iterations").get<long>();
  l.newton_unconverged = j.at("newton_unconverged").get<long>();
  l.repartitions = j.at("repartitions").get<long>();
  l.repartition_times = j.at("repartition_times").get<std::vector<double>>();
  if (l.repartition_times.size() > kRepartitionTimesKept) throw std::out_of_range("loops: more repartition times than are kept");
}

}  // namespace

json trajectoryJson(const Trajectory& tr) {
  json q = json::array(), u = json::array(), poses = json::array();
  for (size_t k = 0; k < tr.size(); ++k) {
    q.push_back(vectorJson(tr.q[k]));
    u.push_back(vectorJson(tr.u[k]));
    poses.push_back(posesJson(tr.poses[k]));
  }
  return {{"scene", tr.scene},          {"q_names", tr.q_names},   {"u_names", tr.u_names},
          {"angle_coordinates", tr.angle_coords},
          {"body_names", tr.body_names}, {"t", tr.t},               {"q", q},
          {"u", u},                      {"energy", tr.energy},     {"kinetic", tr.kinetic},
          {"dissipated", tr.dissipated}, {"poses", poses},          {"status", outcomeName(tr.status())},
          {"failure", tr.failure},       {"failure_kind", failureName(tr.failure_kind)},
          {"failure_time", tr.failure_time}, {"run_time_s", tr.run_time_s},
          {"steps", tr.steps},           {"rhs_evals", tr.rhs_evals}, {"step_retries", tr.step_retries},
          {"grid_cut_steps", tr.grid_cut_steps}, {"loops", loopStatsJson(tr)}};
}

Trajectory trajectoryFromJson(const json& j, const RunSpec& run, const std::string& source) {
  Trajectory tr;
  tr.run = run;
  try {
    tr.scene = j.at("scene").get<std::string>();
    tr.q_names = j.at("q_names").get<std::vector<std::string>>();
    tr.u_names = j.at("u_names").get<std::vector<std::string>>();
    tr.body_names = j.at("body_names").get<std::vector<std::string>>();
    tr.angle_coords = j.at("angle_coordinates").get<std::vector<int>>();
    for (int i : tr.angle_coords)
      if (i < 0 || i >= static_cast<int>(tr.q_names.size())) throw std::out_of_range("angle_coordinates: index out of range");
    tr.t = j.at("t").get<std::vector<double>>();
    for (const json& v : j.at("q")) tr.q.push_back(vectorFrom(v));
    for (const json& v : j.at("u")) tr.u.push_back(vectorFrom(v));
    for (const json& v : j.at("poses")) tr.poses.push_back(posesFrom(v));
    tr.energy = j.at("energy").get<std::vector<double>>();
    tr.kinetic = j.at("kinetic").get<std::vector<double>>();
    tr.dissipated = j.at("dissipated").get<std::vector<double>>();
    const std::string status = j.at("status").get<std::string>();
    tr.failure = j.at("failure").get<std::string>();
    tr.failure_time = j.at("failure_time").get<double>();
    tr.run_time_s = j.at("run_time_s").get<double>();
    tr.steps = j.at("steps").get<long>();
    tr.rhs_evals = j.at("rhs_evals").get<long>();
    tr.step_retries = j.at("step_retries").get<long>();
    tr.grid_cut_steps = j.value("grid_cut_steps", 0L);  // absent in trajectories written before it was counted
    loopStatsFrom(j.value("loops", json(nullptr)), tr);  // absent (a tree) in trajectories written before mechanisms ran outside
    const std::string kind = j.at("failure_kind").get<std::string>();
    for (const FailureInfo& f : failureTable())
      if (kind == f.name) tr.failure_kind = f.id;
    if (status != outcomeName(tr.status())) throw std::runtime_error("status " + status + " against failure_kind " + kind);
  } catch (const std::exception& e) {
    throw std::runtime_error(source + ": not a trajectory this version wrote (" + e.what() + ")");
  }
  const size_t n = tr.t.size();
  if (tr.q.size() != n || tr.u.size() != n || tr.poses.size() != n || tr.energy.size() != n || tr.kinetic.size() != n ||
      tr.dissipated.size() != n)
    throw std::runtime_error(source + ": sample counts differ between t, q, u, poses and energies");
  return tr;
}

}  // namespace em
