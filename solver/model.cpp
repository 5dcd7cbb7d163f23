#include "solver/model.hpp"

#include "solver/text.hpp"

#include <iterator>
#include <unordered_map>

namespace em {

namespace {
constexpr bool jointRowsInOrder() {
  for (int i = 0; i < static_cast<int>(std::size(kJointTypes)); ++i)
    if (static_cast<int>(kJointTypes[i].type) != i) return false;
  return true;
}
static_assert(jointRowsInOrder(), "kJointTypes: one row per JointType, in its order (jointRow indexes by it)");
constexpr bool loopRowsInOrder() {
  for (int i = 0; i < static_cast<int>(std::size(kLoopTypes)); ++i)
    if (static_cast<int>(kLoopTypes[i].type) != i || kLoopTypes[i].point_rows > kLoopTypes[i].equations) return false;
  return true;
}
static_assert(loopRowsInOrder(), "kLoopTypes: one row per LoopType, in its order (loopRow indexes by it), point rows within its rows");
}  // namespace

const std::vector<JointTypeInfo>& jointTypeTable() {
  static const std::vector<JointTypeInfo> table(std::begin(kJointTypes), std::end(kJointTypes));
  return table;
}

namespace {

// §1: names non-empty and unique, parents in range and not the body itself.
void validate(const std::vector<BodyDef>& defs) {
  const int n = static_cast<int>(defs.size());
  if (n == 0) throw std::invalid_argument("a model needs at least one body");
  std::unordered_map<std::string, int> by_name;
  for (int f = 0; f < n; ++f) {
    const BodyDef& b = defs[f];
    if (b.name.empty()) throw ModelError(f, "name", "empty name");
    if (auto [it, fresh] = by_name.emplace(b.name, f); !fresh)
      throw ModelError(f, "name", "duplicate name '" + b.name + "' (first at body " + std::to_string(it->second) + ")");
    if (b.parent < -1 || b.parent >= n) throw ModelError(f, "parent", "parent index out of range");
    if (b.parent == f) throw ModelError(f, "parent", "a body cannot be its own parent");
  }
  // Coordinates are named "<prefix>.q0": the prefixes (a joint's name, else
  // its body's) must be unique too, or two coordinates would share a name.
  std::unordered_map<std::string, int> by_prefix;
  for (int f = 0; f < n; ++f)
    if (auto [it, fresh] = by_prefix.emplace(defs[f].joint.prefix(defs[f].name), f); !fresh)
      throw ModelError(f, defs[f].joint.name.empty() ? "name" : "joint.name",
                       "coordinates named '" + it->first + ".q*' twice (first at body " + std::to_string(it->second) + ")");
}

// §1: depth-first from the ground, children in source order, with an explicit
// stack (no recursion on a depth the input chooses). A body never reached
// hangs from a cycle.
std::vector<int> regularOrder(const std::vector<BodyDef>& defs) {
  const int n = static_cast<int>(defs.size());
  std::vector<std::vector<int>> kids(n);
  std::vector<int> stack, order;
  for (int f = n - 1; f >= 0; --f) {  // reversed, so that the stack pops in source order
    if (defs[f].parent < 0) stack.push_back(f);
    else kids[defs[f].parent].push_back(f);
  }
  order.reserve(n);
  while (!stack.empty()) {
    const int f = stack.back();
    stack.pop_back();
    order.push_back(f);
    stack.insert(stack.end(), kids[f].begin(), kids[f].end());
  }
  if (static_cast<int>(order.size()) < n) {
    std::vector<bool> reached(n, false);
    for (int f : order) reached[f] = true;
    for (int f = 0; f < n; ++f)
      if (!reached[f]) throw ModelError(f, "parent", "cycle: '" + defs[f].name + "' does not reach the ground");
  }
  return order;
}

// Bodies in regular order with their offsets in the internal and the source-order state.
void placeBodies(const std::vector<BodyDef>& defs, const std::vector<int>& order, Model& m) {
  const int n = static_cast<int>(defs.size());
  m.file_to_internal.assign(n, -1);
  for (int i = 0; i < n; ++i) m.file_to_internal[order[i]] = i;
  m.bodies.resize(n);
  for (int i = 0; i < n; ++i) {
    const BodyDef& s = defs[order[i]];
    Body& b = m.bodies[i];
    b.name = s.name;
    b.parent = s.parent < 0 ? -1 : m.file_to_internal[s.parent];
    b.mass = s.mass;
    b.J = s.inertia;
    b.joint = s.joint;
    b.file_index = order[i];
    b.iq = m.nq;
    b.iu = m.nu;
    m.nq += b.nq();
    m.nu += b.nu();
    m.has_springs = m.has_springs || b.joint.has_spring;
    m.has_dampers = m.has_dampers || (b.joint.has_spring && (b.joint.spring.c.array() != 0).any());
    m.has_drives = m.has_drives || b.joint.torque.size() > 0;
    if (b.joint.control) {
      if (m.has_control && b.joint.control->period != m.control_period)
        throw ModelError(order[i], "joint.control.period", "every controlled joint shares one period (one controller): " +
                                                                 gnum(b.joint.control->period) + " s against " + gnum(m.control_period) + " s");
      m.has_control = true;
      m.control_period = b.joint.control->period;
    }
    m.has_sliding = m.has_sliding || b.nt() > 0;
    if (b.parent >= 0) m.bodies[b.parent].children.push_back(i);
    m.body_parent.push_back(b.parent);
    m.body_iu.push_back(b.iu);
    m.body_nu.push_back(b.nu());
    m.body_nt.push_back(b.nt());
  }
  for (const Body& b : m.bodies)
    if (const std::optional<JointLimits>& l = b.joint.limits)
      for (int k = 0; k < b.nq(); ++k)
        m.limited.push_back({b.iq + k, b.iu + k, l->lower[k], l->upper[k], l->restitution,
                             b.joint.prefix(b.name) + ".q" + std::to_string(k)});
  int fq = 0, fu = 0;
  for (int f = 0; f < n; ++f) {
    Body& b = m.bodies[m.file_to_internal[f]];
    b.file_iq = fq;
    b.file_iu = fu;
    fq += b.nq();
    fu += b.nu();
  }
}

}  // namespace

namespace {

// The mechanism's bodies in internal numbering (source indices in, checked by io/).
void placeMechanism(const MechanismDef& def, Model& m) {
  const auto internal = [&m](Attachment a) {
    if (a.body >= 0) a.body = m.file_to_internal.at(a.body);
    return a;
  };
  for (Loop l : def.loops) {
    l.a = internal(l.a), l.b = internal(l.b);
    m.loop_rows += loopRow(l.type).equations;
    m.loops.push_back(std::move(l));
  }
  for (PointSpring s : def.springs) {
    s.a = internal(s.a), s.b = internal(s.b);
    m.has_dampers = m.has_dampers || s.c != 0;
    m.point_springs.push_back(std::move(s));
  }
  // W_diss is the work the non-conservative forces take out: a drive's is counted negative.
  m.has_dampers = m.has_dampers || m.has_drives || m.has_control;
}

// Every body's R (world <- body) at q0, parents first, as formKinematics forms it (docs/theory.md §3).
std::vector<Mat3> rotationsAtStart(const Model& m) {
  std::vector<Mat3> R(m.bodies.size());
  for (int i = 0; i < m.n(); ++i) {
    const Body& b = m.bodies[i];
    const Mat3 R_p = b.parent < 0 ? Mat3::Identity() : R[b.parent];
    R[i] = R_p * jointRow(b.joint.type).kinematics->rotation(b.joint, b.joint.q0.data());
  }
  return R;
}

// The turn each loop that holds one keeps: R_a^T R_b at the initial state (Loop::rel).
void holdStartTurns(Model& m) {
  bool any = false;
  for (const Loop& l : m.loops) any = any || loopRow(l.type).holds_turn;
  if (!any) return;
  const std::vector<Mat3> R = rotationsAtStart(m);
  const auto at = [&R](int body) { return body < 0 ? Mat3::Identity() : R[body]; };
  for (Loop& l : m.loops)
    if (loopRow(l.type).holds_turn) l.rel = at(l.a.body).transpose() * at(l.b.body);
}

// Each loop's speeds: the union of its two bodies' paths to the ground (Model::loop_speeds).
void loopSpeeds(Model& m) {
  m.loop_speeds.clear();
  for (const Loop& l : m.loops) {
    std::vector<char> on(m.nu, 0);
    for (int body : {l.a.body, l.b.body})
      for (int k = body; k >= 0; k = m.body_parent[k])
        for (int j = 0; j < m.body_nu[k]; ++j) on[m.body_iu[k] + j] = 1;
    std::vector<int>& speeds = m.loop_speeds.emplace_back();
    for (int j = 0; j < m.nu; ++j)
      if (on[j]) speeds.push_back(j);
  }
}

}  // namespace

Model buildModel(const std::string& name, const Vec3& gravity, const std::vector<BodyDef>& defs, const MechanismDef& mechanism) {
  validate(defs);
  Model m;
  m.name = name;
  m.gravity = gravity;
  m.has_gravity = gravity.squaredNorm() > 0;
  placeBodies(defs, regularOrder(defs), m);
  placeMechanism(mechanism, m);
  holdStartTurns(m);
  loopSpeeds(m);
  // §2: T(j,i) = 1 when joint j lies on the path from the ground to body i.
  const int n = m.n();
  m.T = Eigen::MatrixXi::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = i; j >= 0; j = m.bodies[j].parent) m.T(j, i) = 1;
  return m;
}

Model withInitialState(Model m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  for (Body& b : m.bodies) {
    b.joint.q0 = q.segment(b.iq, b.nq());
    b.joint.u0 = u.segment(b.iu, b.nu());
  }
  return m;
}

Eigen::VectorXd Model::q0() const {
  Eigen::VectorXd q(nq);
  for (const Body& b : bodies) q.segment(b.iq, b.nq()) = b.joint.q0;
  return q;
}

Eigen::VectorXd Model::u0() const {
  Eigen::VectorXd u(nu);
  for (const Body& b : bodies) u.segment(b.iu, b.nu()) = b.joint.u0;
  return u;
}

namespace {
// p[source index] = internal index, over coordinates (or speeds).
std::vector<int> filePermutation(const Model& m, bool speeds) {
  std::vector<int> p(speeds ? m.nu : m.nq);
  for (const Body& b : m.bodies) {
    const int k = speeds ? b.nu() : b.nq(), internal = speeds ? b.iu : b.iq, file = speeds ? b.file_iu : b.file_iq;
    for (int c = 0; c < k; ++c) p[file + c] = internal + c;
  }
  return p;
}

void permuteToFile(const Model& m, bool speeds, const Eigen::Ref<const Eigen::VectorXd>& in, Eigen::VectorXd& out) {
  out.resize(in.size());
  for (const Body& b : m.bodies) {
    const int k = speeds ? b.nu() : b.nq(), internal = speeds ? b.iu : b.iq, file = speeds ? b.file_iu : b.file_iq;
    out.segment(file, k) = in.segment(internal, k);
  }
}

std::vector<std::string> coordNames(const Model& m, bool speeds) {
  std::vector<std::string> names(speeds ? m.nu : m.nq);
  for (const Body& b : m.bodies) {
    const int k = speeds ? b.nu() : b.nq(), at = speeds ? b.file_iu : b.file_iq;
    for (int c = 0; c < k; ++c) names[at + c] = b.joint.prefix(b.name) + (speeds ? ".u" : ".q") + std::to_string(c);
  }
  return names;
}
}  // namespace

void Model::qToFile(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::VectorXd& qf) const {
  permuteToFile(*this, false, q, qf);
}
void Model::uToFile(const Eigen::Ref<const Eigen::VectorXd>& u, Eigen::VectorXd& uf) const {
  permuteToFile(*this, true, u, uf);
}
std::vector<int> Model::qFilePermutation() const { return filePermutation(*this, false); }
std::vector<int> Model::uFilePermutation() const { return filePermutation(*this, true); }
std::vector<std::string> Model::qNames() const { return coordNames(*this, false); }
std::vector<std::string> Model::uNames() const { return coordNames(*this, true); }

std::vector<int> Model::angleCoordinates() const {
  std::vector<int> idx;
  for (int f = 0; f < n(); ++f) {
    const Body& b = bodies[file_to_internal[f]];
    if (jointQuat(b.joint.type) >= 0) continue;  // compared by pose
    for (int k = b.nt(); k < b.nq(); ++k) idx.push_back(b.file_iq + k);
  }
  return idx;
}

std::string beyondStateBounds(const Model& m, const Eigen::VectorXd& q, const Eigen::VectorXd& u) {
  const std::vector<std::string> qn = m.qNames(), un = m.uNames();
  const auto beyond = [](const std::string& what, double x, double bound, const char* unit) {
    if (!std::isfinite(x)) return what + " not finite";
    if (std::abs(x) <= bound) return std::string();
    const auto [value, edge] = gnumApart(std::abs(x), bound);
    return what + " " + (x < 0 ? "-" : "") + value + " " + unit + " beyond +-" + edge + " " + unit;
  };
  for (const Body& b : m.bodies) {
    const int quat = jointQuat(b.joint.type);
    for (int k = 0; k < b.nq(); ++k) {
      const std::string name = "q " + qn[b.file_iq + k];
      const double x = q[b.iq + k];
      std::string why;
      if (k < b.nt()) why = beyond(name + ": displacement", x, kMaxDisplacement, "m");
      else if (quat < 0) why = beyond(name + ": angle", x, kMaxAngle, "rad");
      else if (k == quat) {
        const double norm = q.segment<4>(b.iq + quat).norm();
        if (!(std::abs(norm - 1) <= kUnitQuatTol))
          why = name + " (a quaternion's first): norm " + gnum(norm) + ", not 1 within " + gnum(kUnitQuatTol);
      }
      if (!why.empty()) return why;
    }
    for (int k = 0; k < b.nu(); ++k) {
      const std::string why = beyond("u " + un[b.file_iu + k] + ": speed", u[b.iu + k], kMaxSpeed, k < b.nt() ? "m/s" : "rad/s");
      if (!why.empty()) return why;
    }
  }
  return {};
}

void randomState(const Model& m, std::mt19937& rng, Eigen::VectorXd& q, Eigen::VectorXd& u) {
  std::uniform_real_distribution<double> ang(-M_PI, M_PI), spd(-2.0, 2.0), disp(-1.0, 1.0);
  std::normal_distribution<double> gauss;
  q.resize(m.nq);
  u.resize(m.nu);
  for (const Body& b : m.bodies) {
    const int quat = jointQuat(b.joint.type);
    for (int k = 0; k < b.nt(); ++k) q[b.iq + k] = disp(rng);
    if (quat >= 0) {
      Vec4 v(gauss(rng), gauss(rng), gauss(rng), gauss(rng));
      q.segment<4>(b.iq + quat) = v.normalized();
    } else {
      for (int k = b.nt(); k < b.nq(); ++k) q[b.iq + k] = ang(rng);
      if (jointRow(b.joint.type).middle_locks) q[b.iq + 1] *= 1.2 / M_PI;  // middle angle within +-72 deg
    }
    for (int k = 0; k < b.nu(); ++k) u[b.iu + k] = spd(rng);
  }
}

}  // namespace em
