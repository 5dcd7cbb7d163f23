#include "compare/crosscheck.hpp"

#include <memory>
#include <optional>
#include <random>

#include "io/json_input.hpp"
#include "reference/mujoco_peer.hpp"
#include "reference/simbody_reference.hpp"
#include "solver/formation.hpp"

namespace em {

namespace {

struct Inhouse {
  Eigen::MatrixXd A;
  Eigen::VectorXd B, udot;
};

Inhouse inhouseAt(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  Workspace ws(m);
  formEquations(m, q.data(), u.data(), ws);
  return {ws.A, ws.B, ws.A.llt().solve(ws.B)};
}

// MuJoCo as it can take the scene: its own URDF reader, else the Model as MJCF.
std::unique_ptr<MujocoPeer> mujocoFor(const Scene& scene, const UrdfOptions& urdf) {
  if (scene.source.format != "urdf") return std::make_unique<MujocoPeer>(scene.model);
  return std::make_unique<MujocoPeer>(scene.model, readFile(scene.source.file, "URDF file"), scene.source_joints,
                                      urdf.lock_joints, urdf.balance_inertia,
                                      urdf.floating_base ? kFloatingBaseJoint : "");
}

// The model with MuJoCo's compiled mass properties in place of the in-house
// ones, joint points kept: what remains between it and MuJoCo is not inertia.
Model withMass(const Model& m, const std::vector<CompiledMass>& mj) {
  std::vector<Vec3> point(m.n()), cm_mj(m.n());  // joint point and MuJoCo's CM, world, zero configuration
  std::vector<Vec3> cm(m.n());
  for (int i = 0; i < m.n(); ++i) {  // parents first: the in-house CMs at zero coordinates
    const Body& b = m.bodies[i];
    point[i] = (b.parent < 0 ? Vec3::Zero() : cm[b.parent]) + b.joint.in_parent;
    cm[i] = point[i] - b.joint.in_body;
  }
  std::vector<BodyDef> defs(m.n());
  for (int i = 0; i < m.n(); ++i) {
    const Body& b = m.bodies[i];
    BodyDef& d = defs[b.file_index];
    d = {b.name, b.parent < 0 ? -1 : m.bodies[b.parent].file_index, mj[i].m, mj[i].J, b.joint};
    d.joint.in_parent = point[i] - (b.parent < 0 ? Vec3::Zero() : mj[b.parent].c);
    d.joint.in_body = point[i] - mj[i].c;
  }
  return buildModel(m.name, m.gravity, defs);
}

void compare(const Model& m, MujocoPeer& mj, const std::string& engine, int k, const Eigen::VectorXd& q,
             const Eigen::VectorXd& u, CrossCheck& c) {
  const Inhouse in = inhouseAt(m, q, u);
  mj.setState(q, u);
  mj.forward();
  c.rows.push_back({k, engine, relativeDifference(mj.massMatrix(), in.A), relativeDifference(mj.rhs(), in.B), relativeDifference(mj.acceleration(), in.udot)});
}

}  // namespace

double relativeDifference(const Eigen::MatrixXd& x, const Eigen::MatrixXd& y) {
  const double scale = y.cwiseAbs().maxCoeff();
  return (x - y).cwiseAbs().maxCoeff() / (scale > 0 ? scale : 1.0);
}

CrossCheck crossCheck(const Scene& scene, const UrdfOptions& urdf, int states, unsigned seed) {
  const Model& m = scene.model;
  CrossCheck c;
  SimbodyReference simbody(m);
  std::unique_ptr<MujocoPeer> mujoco;
  try {
    mujoco = mujocoFor(scene, urdf);
  } catch (const std::exception& e) {
    c.skipped.push_back(std::string("mujoco: ") + e.what());
  }
  std::optional<Model> with_mj_mass;
  if (mujoco) with_mj_mass = withMass(m, mujoco->compiledMass());
  std::mt19937 rng(seed);
  Eigen::VectorXd q = m.q0(), u = m.u0();
  for (int k = 0; k <= states; ++k) {
    if (k > 0) randomState(m, rng, q, u);
    const Inhouse in = inhouseAt(m, q, u);
    simbody.setState(q, u);
    c.rows.push_back({k, "simbody", relativeDifference(simbody.massMatrix(), in.A), relativeDifference(simbody.rhs(), in.B),
                      relativeDifference(simbody.udot(), in.udot)});
    if (!mujoco) continue;
    compare(m, *mujoco, "mujoco", k, q, u, c);
    compare(*with_mj_mass, *mujoco, kMujocoMass, k, q, u, c);
  }
  return c;
}

}  // namespace em
