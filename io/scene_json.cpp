#include "io/scene_json.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "io/json_input.hpp"
#include "solver/applied_forces.hpp"
#include "solver/formation.hpp"
#include "solver/mechanism/assembly.hpp"
#include "solver/mechanism/loops.hpp"
#include "solver/run_spec.hpp"
#include "solver/text.hpp"

namespace em {

Assembly assembledStart(const Model& m, const std::string& what) {
  const Assembly a = assembleStart(m, kLoopStartTol * 1e-3, kAssembleIterations);
  if (!a.converged)
    throw std::runtime_error("Gauss-Newton did not close the loops from the " + what + " (gap " + gnum(a.gap, 3) + ") in " +
                             std::to_string(kAssembleIterations) + " steps");
  return a;
}


namespace {

using json = nlohmann::json;
using Err = InputError;

// Relative tolerance of the inertia checks: equality in the triangle
// inequalities (a thin plate) must pass despite rounding of written decimals.
constexpr double kInertiaRelTol = 1e-9;
// Smallest principal moment accepted, relative to the largest: the 3x3
// eigensolver resolves it to ~eps/kInertiaMinRatio (1e-4 relative) and a rod
// whose axial moment is 1e-9 of its transverse one (the extreme gallery's
// thin_rods) is a real body.
constexpr double kInertiaMinRatio = 1e-12;
// Universal axes count as perpendicular when |cos| is below this (scene-format.md).
constexpr double kPerpendicularTol = 1e-9;
// |q0| and |u0| are held to the model's state bounds (solver/model.hpp:
// kMaxAngle, kMaxDisplacement, kMaxSpeed).
constexpr size_t kMaxNameLength = 64;

std::string at(const std::string& path, const std::string& key) { return jsonPath(path, key); }
std::string at(const std::string& path, size_t i) { return jsonPath(path, i); }

// Every key must be known for its object; "x-" keys are free.
// Scene, body and joint names end up in file names and CSV headers: letters,
// digits, '_' and '-', 1 to 64 of them (docs/scene-format.md).
std::string name(const json& v, const std::string& path) {
  const std::string n = stringAt(v, path);
  if (n.empty()) throw Err(path, "empty name");
  if (!isSceneName(n))
    throw Err(path, "name \"" + printable(n, 40) + "\" has characters outside letters, digits, '_' and '-' (or is over " +
                        std::to_string(kMaxNameLength) + " long)");
  return n;
}

// The "x-" keys of an object (free for comments and provenance), kept as written.
json extras(const json& obj) {
  json x = json::object();
  for (auto it = obj.begin(); it != obj.end(); ++it)
    if (it.key().rfind("x-", 0) == 0) x[it.key()] = it.value();
  return x;
}

Eigen::VectorXd numbers(const json& v, const std::string& path, int min_len, int max_len = -1) {
  if (max_len < 0) max_len = min_len;
  if (!v.is_array()) throw Err(path, "expected a list of numbers");
  const int len = static_cast<int>(v.size());
  if (len < min_len || len > max_len)
    throw Err(path, "expected " + std::to_string(min_len) +
                        (max_len != min_len ? " or " + std::to_string(max_len) : "") +
                        (max_len == 1 ? " number" : " numbers") + ", got " + std::to_string(len));
  Eigen::VectorXd x(len);
  for (int i = 0; i < len; ++i) x[i] = numberAt(v[i], at(path, i));
  return x;
}

Vec3 vec3(const json& v, const std::string& path) { return numbers(v, path, 3); }

// Normalized without underflow or overflow (Eigen's stableNorm): [1e-160, 0, 0]
// is the x axis; only an exactly zero vector is refused. Every engine gets this axis.
Vec3 unitAxis(const json& v, const std::string& path) {
  const Vec3 a = vec3(v, path);
  if (!(a.stableNorm() > 0)) throw Err(path, "zero axis");
  return a.stableNormalized();
}

Mat3 inertia(const json& v, const std::string& path) {
  const Eigen::VectorXd x = numbers(v, path, 3, 6);
  if (x.size() != 3 && x.size() != 6) throw Err(path, "expected 3 or 6 numbers");
  Mat3 J = x.head<3>().asDiagonal();
  if (x.size() == 6) {
    J(0, 1) = J(1, 0) = x[3];
    J(0, 2) = J(2, 0) = x[4];
    J(1, 2) = J(2, 1) = x[5];
  }
  const Vec3 I = Eigen::SelfAdjointEigenSolver<Mat3>(J).eigenvalues();  // ascending
  const double scale = I.cwiseAbs().maxCoeff();
  if (!(I[0] > kInertiaMinRatio * scale) || !(scale > 0))
    throw Err(path, "not positive definite (principal moments " + gnum(I[0]) + ", " + gnum(I[1]) + ", " +
                        gnum(I[2]) + ")");
  if (!(scale >= kInertiaMin && scale <= kInertiaMax))
    throw Err(path, "largest principal moment " + gnum(scale) + " kg m^2 outside [" + gnum(kInertiaMin) + ", " + gnum(kInertiaMax) + "]");
  if (I[0] + I[1] < I[2] * (1 - kInertiaRelTol))
    throw Err(path, "violates the triangle inequality (principal moments " + gnum(I[0]) + " + " + gnum(I[1]) +
                        " < " + gnum(I[2]) + ")");
  return J;
}

JointType jointType(const json& v, const std::string& path) {
  const std::string t = stringAt(v, path);
  std::string known;
  for (const JointTypeInfo& row : jointTypeTable()) {
    if (t == row.name) return row.type;
    known += (known.empty() ? "" : ", ") + std::string(row.name);
  }
  throw Err(path, "unknown joint type '" + printable(t, 40) + "' (" + known + ")");
}

// k or c: one number for every coordinate, or one per coordinate; >= 0.
// |x| within kMaxForceCoefficient (a stiffness, a damping, a torque).
double forceCoefficient(double x, const std::string& path) {
  if (std::abs(x) > kMaxForceCoefficient)
    throw Err(path, gnum(x) + " beyond +-" + gnum(kMaxForceCoefficient) + " (SI), the bound of a stiffness, damping or torque");
  return x;
}

Eigen::VectorXd perCoordinate(const json& v, const std::string& path, int nu) {
  Eigen::VectorXd x = v.is_array() ? numbers(v, path, nu) : Eigen::VectorXd::Constant(nu, numberAt(v, path));
  for (int i = 0; i < nu; ++i) {
    if (x[i] < 0) throw Err(v.is_array() ? at(path, i) : path, "must be >= 0");
    forceCoefficient(x[i], v.is_array() ? at(path, i) : path);
  }
  return x;
}

Spring spring(const json& v, const std::string& path, int nu) {
  if (!v.is_object()) throw Err(path, "expected an object {k, c, q_rest}");
  onlyKeys(v, path, {"k", "c", "q_rest"});
  Spring s;
  s.k = v.contains("k") ? perCoordinate(v["k"], at(path, "k"), nu) : Eigen::VectorXd::Zero(nu);
  s.c = v.contains("c") ? perCoordinate(v["c"], at(path, "c"), nu) : Eigen::VectorXd::Zero(nu);
  s.q_rest = v.contains("q_rest") ? numbers(v["q_rest"], at(path, "q_rest"), nu) : Eigen::VectorXd::Zero(nu);
  return s;
}

// The axes of a joint whose row names one (`axis`) or two (`axes`); keys its kind
// does not take are errors, and so is a spring on a quaternion's coordinates.
void readJointAxes(const json& v, const std::string& path, Joint& j) {
  const std::string kind = jointTypeName(j.type);
  auto forbid = [&](const char* key, bool allowed) {
    if (!allowed && v.contains(key)) throw Err(at(path, key), "not allowed on a " + kind + " joint");
  };
  const int naxes = jointAxes(j.type);
  forbid("axis", naxes == 1);
  forbid("axes", naxes == 2);
  forbid("spring", jointQuat(j.type) < 0);
  if (naxes == 1) j.axis[0] = unitAxis(requireKey(v, path, "axis"), at(path, "axis"));
  if (naxes == 2) {
    const std::string p = at(path, "axes");
    const json& a = requireKey(v, path, "axes");
    if (!a.is_array() || a.size() != 2) throw Err(p, "expected two axes");
    j.axis[0] = unitAxis(a[0], at(p, 0));
    j.axis[1] = unitAxis(a[1], at(p, 1));
    if (std::abs(j.axis[0].dot(j.axis[1])) > kPerpendicularTol) throw Err(p, "axes are not perpendicular");
  }
}

// "limits": {"lower": [...], "upper": [...], "restitution": e}, one bound per
// coordinate of a joint whose q' = u (docs/scene-format.md); its q0 within them.
JointLimits jointLimits(const json& v, const std::string& path, const Joint& j) {
  if (!v.is_object()) throw Err(path, "expected an object {\"lower\", \"upper\", \"restitution\"}");
  onlyKeys(v, path, {"lower", "upper", "restitution"});
  const int nq = jointNq(j.type), nt = jointNt(j.type);
  if (jointQuat(j.type) >= 0 || nq != jointNu(j.type))
    throw Err(path, std::string("a ") + jointTypeName(j.type) + " joint's coordinates are not integrated as q' = u (a quaternion): no limits");
  JointLimits l;
  l.lower = numbers(requireKey(v, path, "lower"), at(path, "lower"), nq, nq);
  l.upper = numbers(requireKey(v, path, "upper"), at(path, "upper"), nq, nq);
  for (int k = 0; k < nq; ++k) {
    const double bound = k < nt ? kMaxDisplacement : kMaxAngle;
    for (const auto& [x, key] : {std::pair{l.lower[k], "lower"}, std::pair{l.upper[k], "upper"}})
      if (std::abs(x) > bound) throw Err(at(at(path, key), k), gnumApart(x, std::copysign(bound, x)).first + " beyond +-" + gnum(bound) + (k < nt ? " m" : " rad"));
    if (!(l.lower[k] < l.upper[k]))
      throw Err(at(at(path, "lower"), k), gnum(l.lower[k]) + " is not below upper " + gnum(l.upper[k]));
    if (!(j.q0[k] >= l.lower[k] && j.q0[k] <= l.upper[k]))
      throw Err(at(at(path, "lower"), k), "q0 " + gnum(j.q0[k]) + " lies outside [" + gnum(l.lower[k]) + ", " + gnum(l.upper[k]) + "]");
  }
  l.restitution = numberAt(requireKey(v, path, "restitution"), at(path, "restitution"));
  if (!(l.restitution >= 0 && l.restitution <= 1)) throw Err(at(path, "restitution"), "must be in [0, 1], got " + gnum(l.restitution));
  return l;
}

// Bounds of a controller's inputs (docs/scene-format.md, joint.control): a
// table's points, a sine's frequency and the sampling period.
constexpr size_t kMaxTablePoints = 100000;
constexpr double kMaxFrequencyHz = 1e4;
constexpr double kMinControlPeriod = 1e-6, kMaxControlPeriod = 1e3;
constexpr double kMaxTableTime = 1e6;

// A coordinate's value of a joint's: a displacement (the first nt) or an angle, within the state's bounds.
double coordinateValue(const json& v, const std::string& path, const Joint& j, int k) {
  const double x = numberAt(v, path), bound = k < jointNt(j.type) ? kMaxDisplacement : kMaxAngle;
  if (std::abs(x) > bound) throw Err(path, gnumApart(x, std::copysign(bound, x)).first + " beyond +-" + gnum(bound) + (k < jointNt(j.type) ? " m" : " rad"));
  return x;
}

// One value per coordinate ("q", "offset", "amplitude"): a list, or one number for every coordinate.
Eigen::VectorXd coordinateValues(const json& v, const std::string& path, const Joint& j) {
  const int nu = jointNu(j.type);
  if (!v.is_array()) {
    const double x = coordinateValue(v, path, j, nu - 1);
    for (int k = 0; k < nu; ++k) coordinateValue(v, path, j, k);
    return Eigen::VectorXd::Constant(nu, x);
  }
  if (static_cast<int>(v.size()) != nu)
    throw Err(path, "expected " + std::to_string(nu) + (nu == 1 ? " number" : " numbers") + ", got " + std::to_string(v.size()));
  Eigen::VectorXd x(nu);
  for (int k = 0; k < nu; ++k) x[k] = coordinateValue(v[k], at(path, k), j, k);
  return x;
}

// A table: "t" strictly increasing in [0, kMaxTableTime], and its rows under
// `key`, one per time, each nu values (one number where nu is 1); `value`
// checks each entry.
template <class Check>
void table(const json& v, const std::string& path, const char* key, int nu, std::vector<double>& t, Eigen::MatrixXd& rows, Check value) {
  const json& times = requireKey(v, path, "t");
  const json& values = requireKey(v, path, key);
  const std::string pt = at(path, "t"), pv = at(path, key);
  if (!times.is_array() || times.empty()) throw Err(pt, "expected a list of times");
  if (times.size() > kMaxTablePoints) throw Err(pt, std::to_string(times.size()) + " points, over the bound " + std::to_string(kMaxTablePoints));
  if (!values.is_array() || values.size() != times.size())
    throw Err(pv, "expected one row per time (" + std::to_string(times.size()) + ")");
  rows.resize(static_cast<Eigen::Index>(times.size()), nu);
  for (size_t i = 0; i < times.size(); ++i) {
    const double ti = numberAt(times[i], at(pt, i));
    if (!(ti >= 0 && ti <= kMaxTableTime)) throw Err(at(pt, i), gnum(ti) + " s outside [0, " + gnum(kMaxTableTime) + "]");
    if (i > 0 && !(ti > t.back())) throw Err(at(pt, i), gnum(ti) + " s is not after the previous time " + gnum(t.back()) + " s (a table in order)");
    t.push_back(ti);
    const json& row = values[i];
    const std::string pr = at(pv, i);
    if (nu == 1 && !row.is_array()) {
      rows(static_cast<Eigen::Index>(i), 0) = value(row, pr, 0);
      continue;
    }
    if (!row.is_array() || static_cast<int>(row.size()) != nu) throw Err(pr, "expected " + std::to_string(nu) + (nu == 1 ? " number" : " numbers"));
    for (int k = 0; k < nu; ++k) rows(static_cast<Eigen::Index>(i), k) = value(row[k], at(pr, k), k);
  }
}

ControlTarget controlTarget(const json& v, const std::string& path, const Joint& j) {
  if (!v.is_object()) throw Err(path, "expected an object {\"type\": \"constant\" | \"sine\" | \"table\", ...}");
  const std::string type = stringAt(requireKey(v, path, "type"), at(path, "type"));
  const int nu = jointNu(j.type);
  ControlTarget T;
  if (type == "constant") {
    onlyKeys(v, path, {"type", "q"});
    T.type = TargetType::Constant;
    T.q = coordinateValues(requireKey(v, path, "q"), at(path, "q"), j);
  } else if (type == "sine") {
    onlyKeys(v, path, {"type", "offset", "amplitude", "frequency_hz"});
    T.type = TargetType::Sine;
    T.offset = coordinateValues(requireKey(v, path, "offset"), at(path, "offset"), j);
    T.amplitude = coordinateValues(requireKey(v, path, "amplitude"), at(path, "amplitude"), j);
    const json& f = requireKey(v, path, "frequency_hz");
    T.frequency_hz = f.is_array() ? numbers(f, at(path, "frequency_hz"), nu) : Eigen::VectorXd::Constant(nu, numberAt(f, at(path, "frequency_hz")));
    for (int k = 0; k < nu; ++k)
      if (!(T.frequency_hz[k] >= 0 && T.frequency_hz[k] <= kMaxFrequencyHz))
        throw Err(f.is_array() ? at(at(path, "frequency_hz"), k) : at(path, "frequency_hz"), gnum(T.frequency_hz[k]) + " Hz outside [0, " + gnum(kMaxFrequencyHz) + "]");
  } else if (type == "table") {
    onlyKeys(v, path, {"type", "t", "q"});
    T.type = TargetType::Table;
    table(v, path, "q", nu, T.t, T.rows, [&j](const json& x, const std::string& p, int k) { return coordinateValue(x, p, j, k); });
  } else {
    throw Err(at(path, "type"), "unknown target type '" + printable(type, 40) + "' (constant, sine, table)");
  }
  return T;
}

// "control": a PD loop toward a target, or a torque table, continuous or
// sampled every "period" s (docs/scene-format.md, theory.md §18).
JointControl jointControl(const json& v, const std::string& path, const Joint& j, std::optional<double> urdf_effort = std::nullopt) {
  if (!v.is_object()) throw Err(path, "expected an object {\"type\": \"pd\" | \"table\", ...}");
  if (jointQuat(j.type) >= 0 || jointNq(j.type) != jointNu(j.type))
    throw Err(path, std::string("a ") + jointTypeName(j.type) + " joint's coordinates are not integrated as q' = u (a quaternion): no joint-space control");
  const std::string type = stringAt(requireKey(v, path, "type"), at(path, "type"));
  const int nu = jointNu(j.type);
  JointControl c;
  if (type == "pd") {
    onlyKeys(v, path, {"type", "kp", "kd", "target", "effort", "period"});
    c.type = ControlType::Pd;
    c.kp = perCoordinate(requireKey(v, path, "kp"), at(path, "kp"), nu);
    c.kd = perCoordinate(requireKey(v, path, "kd"), at(path, "kd"), nu);
    c.target = controlTarget(requireKey(v, path, "target"), at(path, "target"), j);
    c.effort = Eigen::VectorXd::Constant(nu, std::numeric_limits<double>::infinity());
    if (v.contains("effort") && v["effort"] == "urdf") {  // the URDF joint's own <limit effort>
      if (!urdf_effort) throw Err(at(path, "effort"), "\"urdf\" takes a URDF joint's <limit effort>, and this joint has none (> 0)");
      c.effort = Eigen::VectorXd::Constant(nu, forceCoefficient(*urdf_effort, at(path, "effort")));
    } else if (v.contains("effort")) {
      c.effort = perCoordinate(v["effort"], at(path, "effort"), nu);
      for (int k = 0; k < nu; ++k)
        if (!(c.effort[k] > 0)) throw Err(at(path, "effort"), "must be > 0 (leave the key out for no clamp)");
    }
  } else if (type == "table") {
    onlyKeys(v, path, {"type", "t", "tau", "period"});
    c.type = ControlType::TorqueTable;
    table(v, path, "tau", nu, c.t, c.tau, [](const json& x, const std::string& p, int) { return forceCoefficient(numberAt(x, p), p); });
  } else {
    throw Err(at(path, "type"), "unknown control type '" + printable(type, 40) + "' (pd, table)");
  }
  if (v.contains("period")) {
    c.period = numberAt(v["period"], at(path, "period"));
    if (!(c.period >= kMinControlPeriod && c.period <= kMaxControlPeriod))
      throw Err(at(path, "period"), gnum(c.period) + " s outside [" + gnum(kMinControlPeriod) + ", " + gnum(kMaxControlPeriod) + "] (leave it out for a continuous loop)");
  }
  return c;
}

Joint joint(const json& v, const std::string& path) {
  if (!v.is_object()) throw Err(path, "expected an object");
  Joint j;
  j.type = jointType(requireKey(v, path, "type"), at(path, "type"));
  onlyKeys(v, path, {"type", "name", "axis", "axes", "in_parent", "in_body", "q0", "u0", "spring", "torque", "limits", "control"});
  if (v.contains("name")) j.name = name(v["name"], at(path, "name"));
  readJointAxes(v, path, j);
  j.in_parent = vec3(requireKey(v, path, "in_parent"), at(path, "in_parent"));
  j.in_body = vec3(requireKey(v, path, "in_body"), at(path, "in_body"));
  const int nq = jointNq(j.type), nu = jointNu(j.type), nt = jointNt(j.type), quat = jointQuat(j.type);
  j.q0 = Eigen::VectorXd::Zero(nq);
  if (quat >= 0) j.q0[quat] = 1;
  if (v.contains("q0")) j.q0 = numbers(v["q0"], at(path, "q0"), nq);
  for (int k = 0; k < nt; ++k)
    if (std::abs(j.q0[k]) > kMaxDisplacement)
      throw Err(at(at(path, "q0"), k), "displacement " + gnumApart(j.q0[k], std::copysign(kMaxDisplacement, j.q0[k])).first + " m beyond +-" + gnum(kMaxDisplacement) + " m");
  for (int k = nt; k < nq && quat < 0; ++k)
    if (std::abs(j.q0[k]) > kMaxAngle)
      throw Err(at(at(path, "q0"), k), "angle " + gnumApart(j.q0[k], std::copysign(kMaxAngle, j.q0[k])).first + " rad beyond +-" + gnum(kMaxAngle) +
                                           " rad, where a double no longer resolves 1e-12 rad");
  if (quat >= 0) {
    auto q = j.q0.segment<4>(quat);
    if (!(q.norm() > 0)) throw Err(at(path, "q0"), "zero quaternion");
    q.normalize();
  }
  j.u0 = v.contains("u0") ? numbers(v["u0"], at(path, "u0"), nu) : Eigen::VectorXd::Zero(nu);
  for (int k = 0; k < nu; ++k)
    if (std::abs(j.u0[k]) > kMaxSpeed)
      throw Err(at(at(path, "u0"), k), "speed " + gnumApart(j.u0[k], std::copysign(kMaxSpeed, j.u0[k])).first + (k < nt ? " m/s" : " rad/s") + " beyond +-" +
                                           gnum(kMaxSpeed) + ", the bound of a state's speeds");
  if (v.contains("spring")) {
    j.has_spring = true;
    j.spring = spring(v["spring"], at(path, "spring"), nu);
  }
  if (v.contains("torque")) {  // a drive: one number for every speed, or one per speed
    const json& t = v["torque"];
    j.torque = t.is_array() ? numbers(t, at(path, "torque"), nu) : Eigen::VectorXd::Constant(nu, numberAt(t, at(path, "torque")));
    for (int i = 0; i < nu; ++i) forceCoefficient(j.torque[i], t.is_array() ? at(at(path, "torque"), i) : at(path, "torque"));
  }
  if (v.contains("limits")) j.limits = jointLimits(v["limits"], at(path, "limits"), j);
  if (v.contains("control")) j.control = jointControl(v["control"], at(path, "control"), j);
  return j;
}

LoopType loopType(const json& v, const std::string& path) {
  const std::string t = stringAt(v, path);
  std::string known;
  for (const LoopTypeInfo& row : kLoopTypes) {
    if (t == row.name) return row.type;
    known += (known.empty() ? "" : ", ") + std::string(row.name);
  }
  throw Err(path, "unknown loop type '" + printable(t, 40) + "' (" + known + ")");
}

// body_a, point_a, body_b, point_b of a loop or a force; a body joined to itself is refused.
void readEnds(const json& v, const std::string& path, std::string& body_a, Vec3& point_a, std::string& body_b, Vec3& point_b) {
  body_a = stringAt(requireKey(v, path, "body_a"), at(path, "body_a"));
  body_b = stringAt(requireKey(v, path, "body_b"), at(path, "body_b"));
  point_a = v.contains("point_a") ? vec3(v["point_a"], at(path, "point_a")) : Vec3::Zero();
  point_b = v.contains("point_b") ? vec3(v["point_b"], at(path, "point_b")) : Vec3::Zero();
  for (const auto& [key, p] : {std::pair<const char*, const Vec3&>{"point_a", point_a}, {"point_b", point_b}})
    if (p.cwiseAbs().maxCoeff() > kMaxDisplacement)  // the displacement bound: beyond it a double no longer resolves 1e-12 m
      throw Err(at(path, key), "a coordinate beyond +-" + gnum(kMaxDisplacement) + " m");
  if (body_a == body_b) throw Err(at(path, "body_b"), "joins body '" + printable(body_a, 40) + "' to itself");
}

LoopSpec loop(const json& v, const std::string& path) {
  if (!v.is_object()) throw Err(path, "expected an object");
  LoopSpec l;
  l.type = loopType(requireKey(v, path, "type"), at(path, "type"));
  const LoopAxes axes = loopRow(l.type).axes;
  std::vector<std::string> keys = {"name", "type", "body_a", "point_a", "body_b", "point_b"};
  if (axes != LoopAxes::None) keys.push_back("axis_a");
  if (axes == LoopAxes::AB) keys.push_back("axis_b");
  onlyKeys(v, path, keys);
  l.name = name(requireKey(v, path, "name"), at(path, "name"));
  readEnds(v, path, l.body_a, l.point_a, l.body_b, l.point_b);
  if (axes != LoopAxes::None) l.axis_a = unitAxis(requireKey(v, path, "axis_a"), at(path, "axis_a"));
  if (axes == LoopAxes::AB) l.axis_b = unitAxis(requireKey(v, path, "axis_b"), at(path, "axis_b"));
  l.extra = extras(v);
  return l;
}

ForceSpec force(const json& v, const std::string& path) {
  if (!v.is_object()) throw Err(path, "expected an object");
  onlyKeys(v, path, {"name", "type", "body_a", "point_a", "body_b", "point_b", "k", "c", "length"});
  const std::string type = stringAt(requireKey(v, path, "type"), at(path, "type"));
  if (type != "spring") throw Err(at(path, "type"), "unknown force type '" + printable(type, 40) + "' (spring)");
  ForceSpec f;
  f.name = name(requireKey(v, path, "name"), at(path, "name"));
  readEnds(v, path, f.body_a, f.point_a, f.body_b, f.point_b);
  f.k = numberAt(requireKey(v, path, "k"), at(path, "k"));
  if (!(f.k >= 0)) throw Err(at(path, "k"), "must be >= 0");
  forceCoefficient(f.k, at(path, "k"));
  f.c = v.contains("c") ? numberAt(v["c"], at(path, "c")) : 0.0;
  if (!(f.c >= 0)) throw Err(at(path, "c"), "must be >= 0");
  forceCoefficient(f.c, at(path, "c"));
  f.length = numberAt(requireKey(v, path, "length"), at(path, "length"));
  if (!(f.length > 0)) throw Err(at(path, "length"), "a rest length must be > 0");
  if (f.length > kMaxDisplacement) throw Err(at(path, "length"), gnum(f.length) + " m beyond " + gnum(kMaxDisplacement) + " m");
  f.extra = extras(v);
  return f;
}

// A list of named items (loops, forces): each read by `read`, names unique.
template <class T, class Read>
std::vector<T> namedList(const json& doc, const char* key, Read read) {
  std::vector<T> out;
  if (!doc.contains(key)) return out;
  const json& list = doc[key];
  if (!list.is_array()) throw Err(key, "expected a list");
  for (size_t i = 0; i < list.size(); ++i) {
    out.push_back(read(list[i], at(key, i)));
    for (size_t k = 0; k < i; ++k)
      if (out[k].name == out[i].name)
        throw Err(at(at(key, i), "name"), "duplicate name '" + out[i].name + "' (first at " + at(key, k) + ")");
  }
  return out;
}

BodySpec body(const json& v, const std::string& path) {
  if (!v.is_object()) throw Err(path, "expected an object");
  onlyKeys(v, path, {"name", "parent", "mass", "inertia", "joint"});
  BodySpec b;
  b.name = name(requireKey(v, path, "name"), at(path, "name"));
  b.parent = stringAt(requireKey(v, path, "parent"), at(path, "parent"));
  b.mass = numberAt(requireKey(v, path, "mass"), at(path, "mass"));
  if (!(b.mass > 0)) throw Err(at(path, "mass"), "must be > 0");
  if (!(b.mass >= kMassMin && b.mass <= kMassMax))
    throw Err(at(path, "mass"), gnum(b.mass) + " kg outside [" + gnum(kMassMin) + ", " + gnum(kMassMax) + "]");
  b.inertia = inertia(requireKey(v, path, "inertia"), at(path, "inertia"));
  b.joint = joint(requireKey(v, path, "joint"), at(path, "joint"));
  b.extra = extras(v);
  return b;
}

void simulateDefaults(const json& sim, SceneSpec& s) {
  if (!sim.is_object()) throw Err("simulate", "expected an object");
  onlyKeys(sim, "simulate", {"t_end", "output_dt", "assemble"});
  if (sim.contains("assemble")) {
    if (!sim["assemble"].is_boolean()) throw Err("simulate.assemble", "expected true or false");
    s.assemble = sim["assemble"].get<bool>();
  }
  if (sim.contains("t_end")) s.t_end = numberAt(sim["t_end"], "simulate.t_end");
  if (!(s.t_end > 0)) throw Err("simulate.t_end", "must be > 0");
  if (sim.contains("output_dt")) s.output_dt = numberAt(sim["output_dt"], "simulate.output_dt");
  if (!(s.output_dt > 0)) throw Err("simulate.output_dt", "must be > 0");
  try {
    outputIntervals(s.t_end, s.output_dt);  // the grid rule every run checks, here at load
  } catch (const SettingError& e) {
    throw Err("simulate." + e.field, std::string(e.what()).substr(e.field.size() + 1));
  }
}

// One coordinate of "benchmark.measure": {"name", "body", "point", "axis"}; the body must be one of `bodies`.
BenchmarkPoint benchmarkPoint(const json& v, const std::string& path, const std::vector<BodySpec>& bodies) {
  if (!v.is_object()) throw Err(path, "expected an object {\"name\", \"body\", \"point\", \"axis\"}");
  onlyKeys(v, path, {"name", "body", "point", "axis"});
  BenchmarkPoint b;
  b.name = name(requireKey(v, path, "name"), at(path, "name"));
  b.body = stringAt(requireKey(v, path, "body"), at(path, "body"));
  if (std::none_of(bodies.begin(), bodies.end(), [&](const BodySpec& s) { return s.name == b.body; }))
    throw Err(at(path, "body"), "no body named '" + printable(b.body, 40) + "' (the ground does not move)");
  if (v.contains("point")) b.point = vec3(v["point"], at(path, "point"));
  if (b.point.cwiseAbs().maxCoeff() > kMaxDisplacement)
    throw Err(at(path, "point"), "a coordinate beyond +-" + gnum(kMaxDisplacement) + " m");
  const std::string axis = stringAt(requireKey(v, path, "axis"), at(path, "axis"));
  static const char* kAxes[] = {"x", "y", "z"};
  const auto* hit = std::find(std::begin(kAxes), std::end(kAxes), axis);
  if (hit == std::end(kAxes)) throw Err(at(path, "axis"), "'" + printable(axis, 20) + "' is not a world axis (x, y, z)");
  b.axis = static_cast<int>(hit - std::begin(kAxes));
  return b;
}

// "benchmark.solution": a row per output step, each the measured coordinates in
// "measure"'s order (m, within the displacement bound), flattened row-major.
std::vector<double> benchmarkSolution(const json& v, const std::string& path, const BenchmarkSpec& b) {
  if (!v.is_array() || v.size() != static_cast<size_t>(b.outputs))
    throw Err(path, "expected a row per output step: " + std::to_string(b.outputs) + " rows, got " +
                        (v.is_array() ? std::to_string(v.size()) : describeJson(v)));
  const int width = static_cast<int>(b.measure.size());
  std::vector<double> rows;
  rows.reserve(v.size() * b.measure.size());
  for (size_t k = 0; k < v.size(); ++k) {
    const Eigen::VectorXd row = numbers(v[k], at(path, k), width);
    for (int m = 0; m < width; ++m) {
      if (!(std::abs(row[m]) <= kMaxDisplacement))
        throw Err(at(at(path, k), m), gnum(row[m]) + " m beyond +-" + gnum(kMaxDisplacement) + " m");
      rows.push_back(row[m]);
    }
  }
  return rows;
}

// "benchmark": the scene as a benchmark problem (docs/scene-format.md): its
// error measure, horizon, output steps and precision levels.
BenchmarkSpec benchmark(const json& v, const std::vector<BodySpec>& bodies) {
  const std::string path = "benchmark";
  if (!v.is_object()) throw Err(path, "expected an object");
  std::vector<std::string> keys = {"problem", "measure", "t_end", "outputs", "levels", "solution"};
  for (auto it = v.begin(); it != v.end(); ++it)
    if (it.key().rfind("x-", 0) == 0) keys.push_back(it.key());
  onlyKeys(v, path, keys);
  BenchmarkSpec b;
  b.problem = name(requireKey(v, path, "problem"), at(path, "problem"));
  const json& measure = requireKey(v, path, "measure");
  if (!measure.is_array() || measure.empty() || measure.size() > static_cast<size_t>(kBenchmarkMeasureMax))
    throw Err(at(path, "measure"), "expected a list of 1 to " + std::to_string(kBenchmarkMeasureMax) + " coordinates");
  for (size_t i = 0; i < measure.size(); ++i) {
    b.measure.push_back(benchmarkPoint(measure[i], at(at(path, "measure"), i), bodies));
    for (size_t k = 0; k < i; ++k)
      if (b.measure[k].name == b.measure[i].name)
        throw Err(at(at(at(path, "measure"), i), "name"), "duplicate name '" + b.measure[i].name + "'");
  }
  b.t_end = positiveAt(requireKey(v, path, "t_end"), at(path, "t_end"));
  b.outputs = wholeNumberAt(requireKey(v, path, "outputs"), at(path, "outputs"), 1, kBenchmarkOutputsMax, "output steps");
  try {
    outputIntervals(b.t_end, b.outputStep());  // the grid rule every run checks
  } catch (const SettingError& e) {
    throw Err(at(path, "t_end"), std::string(e.what()).substr(e.field.size() + 1));
  }
  const json& levels = requireKey(v, path, "levels");
  if (!levels.is_array() || levels.empty() || levels.size() > static_cast<size_t>(kBenchmarkLevelsMax))
    throw Err(at(path, "levels"), "expected a list of 1 to " + std::to_string(kBenchmarkLevelsMax) + " precision levels (m)");
  for (size_t i = 0; i < levels.size(); ++i) {
    const std::string p = at(at(path, "levels"), i);
    const double x = positiveAt(levels[i], p);
    if (!(x <= kMaxDisplacement)) throw Err(p, gnum(x) + " m beyond " + gnum(kMaxDisplacement) + " m");
    if (i > 0 && !(x < b.levels.back())) throw Err(p, "levels go from coarse to fine: " + gnum(x) + " is not below " + gnum(b.levels.back()));
    b.levels.push_back(x);
  }
  if (v.contains("solution")) b.solution = benchmarkSolution(v["solution"], at(path, "solution"), b);
  b.extra = extras(v);
  return b;
}

SceneSpec spec(const json& doc) {
  if (!doc.is_object()) throw Err("(document)", "expected a JSON object");
  if (doc.contains("format") && doc["format"] == "eigenmass-plan/1")  // before its keys are blamed one by one
    throw Err("format", "a plan, not a scene (eigenmass-plan/1, docs/sweep.md): `sweep PLAN` runs it; this command takes a scene or a URDF");
  onlyKeys(doc, "", {"format", "name", "gravity", "bodies", "loops", "forces", "simulate", "benchmark"});
  const std::string fmt = stringAt(requireKey(doc, "", "format"), "format");
  if (fmt != "eigenmass-scene/1")
    throw Err("format", "unsupported format '" + printable(fmt, 40) + "' (expected eigenmass-scene/1)");
  SceneSpec s;
  s.name = name(requireKey(doc, "", "name"), "name");
  if (doc.contains("gravity")) s.gravity = vec3(doc["gravity"], "gravity");
  if (!(s.gravity.norm() <= kGravityMax))
    throw Err("gravity", "|g| = " + gnumApart(s.gravity.norm(), kGravityMax).first + " m/s^2 beyond " + gnum(kGravityMax) + " (a thousand g)");
  const json& bodies = requireKey(doc, "", "bodies");
  if (!bodies.is_array()) throw Err("bodies", "expected a list of bodies");
  if (bodies.empty()) throw Err("bodies", "empty body list");
  for (size_t i = 0; i < bodies.size(); ++i) s.bodies.push_back(body(bodies[i], at("bodies", i)));
  s.loops = namedList<LoopSpec>(doc, "loops", loop);
  if (!s.loops.empty())
    for (size_t i = 0; i < s.bodies.size(); ++i)
      if (s.bodies[i].joint.limits)
        throw Err(at(at(at("bodies", i), "joint"), "limits"), "joint limits run on trees: a scene with loops takes none (not built)");
  const BodySpec* controller = nullptr;  // one controller: every controlled joint's period is one
  for (size_t i = 0; i < s.bodies.size(); ++i)
    if (const std::optional<JointControl>& c = s.bodies[i].joint.control) {
      if (controller && c->period != controller->joint.control->period)
        throw Err(at(at(at(at("bodies", i), "joint"), "control"), "period"),
                  gnum(c->period) + " s, but body '" + controller->name + "' is sampled every " + gnum(controller->joint.control->period) +
                      " s: every controlled joint shares one period (one controller; absent: continuous)");
      controller = &s.bodies[i];
    }
  s.forces = namedList<ForceSpec>(doc, "forces", force);
  if (doc.contains("simulate")) simulateDefaults(doc["simulate"], s);
  if (doc.contains("benchmark")) s.benchmark = benchmark(doc["benchmark"], s.bodies);
  s.extra = extras(doc);
  return s;
}

// What every run allocates that grows faster than n: the workspace's A and A'
// and classical's factor of A, three (N x N) matrices, 24 N^2 bytes (N the
// speeds). A scene that cannot fit that in half the machine's memory is
// refused up front instead of ending in std::bad_alloc; an eigenfactor method
// carries more (about 60 N^2 doubles under an adaptive GSL integrator).
void requireMemoryFor(const std::vector<BodySpec>& bodies) {
  double N = 0;
  for (const BodySpec& b : bodies) N += jointNu(b.joint.type);
  const double need = 24.0 * N * N;
  const double have = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGE_SIZE));
  if (have > 0 && need > 0.5 * have)
    throw Err("bodies", std::to_string(bodies.size()) + " bodies (" + gnum(N) + " speeds) need about " +
                            gnum(need / 1e9, 3) + " GB for any run (24 N^2 bytes), more than half of this machine's " +
                            gnum(have / 1e9, 3) + " GB");
}

std::string bodyPath(int file_index, const std::string& key) { return "bodies[" + std::to_string(file_index) + "]." + key; }

// A mechanism's initial state (docs/scene-format.md, "Mechanisms"): its welds
// take their orientation from it; a loop it leaves open, or a point spring
// whose points coincide, is refused naming the item.

void checkMechanismStart(Model& m, bool assemble, Assembly* assembled) {
  if (assemble && m.loops.empty())
    throw Err("simulate.assemble", "the scene has no loops to assemble its start onto (or --assemble was given for a tree)");
  if (!m.isMechanism()) return;
  if (assemble) {
    Assembly a;
    try {
      a = assembledStart(m, "written start");
    } catch (const std::runtime_error& e) {
      throw Err("simulate.assemble", std::string(e.what()) + ": start nearer an assembled position");
    }
    m = withInitialState(std::move(m), a.q, a.u);
    if (assembled) *assembled = a;
  }
  const Eigen::VectorXd q = m.q0(), u = m.u0();
  Workspace ws(m);
  formKinematics(m, q.data(), u.data(), ws);
  for (size_t i = 0; i < m.point_springs.size(); ++i) {
    const PointSpring& s = m.point_springs[i];
    if ((pointMotion(ws, s.a).x - pointMotion(ws, s.b).x).norm() < 1e-12)
      throw Err(at("forces", i), "spring '" + s.name + "': its two points coincide at the initial state (no line to act along)");
  }
  if (const LoopGap gap = openLoop(m, q, u, kLoopStartTol); gap.loop >= 0)
    throw Err(at("loops", static_cast<size_t>(gap.loop)), gap.what + " at the initial state, beyond " + gnum(kLoopStartTol) +
                                                               " (simulate.assemble or --assemble projects the start onto the loops)");
}

}  // namespace

JointControl parseJointControl(const json& v, const std::string& path, const Joint& j, std::optional<double> urdf_effort) {
  return jointControl(v, path, j, urdf_effort);
}

SceneSpec parseSceneSpec(const std::string& text) { return spec(parseJsonStrict(text)); }

bool isSceneName(const std::string& n) {
  return !n.empty() && n.size() <= kMaxNameLength && std::all_of(n.begin(), n.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

namespace {

json numbersJson(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }
json vecJson(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

json tableJson(const std::vector<double>& t, const Eigen::MatrixXd& rows) {
  json r = json::array();
  for (Eigen::Index i = 0; i < rows.rows(); ++i) r.push_back(numbersJson(rows.row(i).transpose()));
  return {{"t", t}, {"rows", r}};
}

json controlJson(const JointControl& c) {
  json o;
  if (c.type == ControlType::TorqueTable) {
    const json tab = tableJson(c.t, c.tau);
    o = {{"type", "table"}, {"t", tab["t"]}, {"tau", tab["rows"]}};
  } else {
    const ControlTarget& T = c.target;
    json target;
    if (T.type == TargetType::Constant) target = {{"type", "constant"}, {"q", numbersJson(T.q)}};
    if (T.type == TargetType::Sine)
      target = {{"type", "sine"}, {"offset", numbersJson(T.offset)}, {"amplitude", numbersJson(T.amplitude)}, {"frequency_hz", numbersJson(T.frequency_hz)}};
    if (T.type == TargetType::Table) {
      const json tab = tableJson(T.t, T.rows);
      target = {{"type", "table"}, {"t", tab["t"]}, {"q", tab["rows"]}};
    }
    o = {{"type", "pd"}, {"kp", numbersJson(c.kp)}, {"kd", numbersJson(c.kd)}, {"target", target}};
    if (std::isfinite(c.effort.maxCoeff())) o["effort"] = numbersJson(c.effort);
  }
  if (c.period > 0) o["period"] = c.period;
  return o;
}

json jointJson(const Joint& j) {
  json o = {{"type", jointTypeName(j.type)}};
  if (!j.name.empty()) o["name"] = j.name;
  if (jointAxes(j.type) == 1) o["axis"] = vecJson(j.axis[0]);
  if (jointAxes(j.type) == 2) o["axes"] = {vecJson(j.axis[0]), vecJson(j.axis[1])};
  o["in_parent"] = vecJson(j.in_parent);
  o["in_body"] = vecJson(j.in_body);
  if (j.q0.size()) o["q0"] = numbersJson(j.q0);
  if (j.u0.size()) o["u0"] = numbersJson(j.u0);
  if (j.has_spring)
    o["spring"] = {{"k", numbersJson(j.spring.k)}, {"c", numbersJson(j.spring.c)}, {"q_rest", numbersJson(j.spring.q_rest)}};
  if (j.torque.size()) o["torque"] = numbersJson(j.torque);
  if (j.limits) o["limits"] = {{"lower", numbersJson(j.limits->lower)}, {"upper", numbersJson(j.limits->upper)}, {"restitution", j.limits->restitution}};
  if (j.control) o["control"] = controlJson(*j.control);
  return o;
}

json loopJson(const LoopSpec& l) {
  json o = {{"name", l.name}, {"type", loopRow(l.type).name}, {"body_a", l.body_a}, {"point_a", vecJson(l.point_a)},
            {"body_b", l.body_b}, {"point_b", vecJson(l.point_b)}};
  if (loopRow(l.type).axes != LoopAxes::None) o["axis_a"] = vecJson(l.axis_a);
  if (loopRow(l.type).axes == LoopAxes::AB) o["axis_b"] = vecJson(l.axis_b);
  o.update(l.extra);
  return o;
}

json forceJson(const ForceSpec& f) {
  json o = {{"name", f.name}, {"type", "spring"}, {"body_a", f.body_a}, {"point_a", vecJson(f.point_a)}, {"body_b", f.body_b},
            {"point_b", vecJson(f.point_b)}, {"k", f.k}, {"c", f.c}, {"length", f.length}};
  o.update(f.extra);
  return o;
}

// `key`'s list, one item per line, or nothing when it is empty.
template <class T, class ToJson>
std::string listText(const char* key, const std::vector<T>& items, ToJson toJson) {
  if (items.empty()) return "";
  std::string text = "  \"" + std::string(key) + "\": [\n";
  for (size_t i = 0; i < items.size(); ++i) text += "    " + toJson(items[i]).dump() + (i + 1 < items.size() ? ",\n" : "\n");
  return text + "  ],\n";
}

json benchmarkJson(const BenchmarkSpec& b) {
  static const char* kAxes[] = {"x", "y", "z"};
  json measure = json::array();
  for (const BenchmarkPoint& p : b.measure)
    measure.push_back({{"name", p.name}, {"body", p.body}, {"point", vecJson(p.point)}, {"axis", kAxes[p.axis]}});
  json o = {{"problem", b.problem}, {"measure", measure}, {"t_end", b.t_end}, {"outputs", b.outputs}, {"levels", b.levels}};
  if (b.hasSolution()) {
    json rows = json::array();
    for (int k = 1; k <= b.outputs; ++k) {
      json row = json::array();
      for (size_t m = 0; m < b.measure.size(); ++m) row.push_back(b.solutionAt(k, m));
      rows.push_back(row);
    }
    o["solution"] = rows;
  }
  o.update(b.extra);
  return o;
}

json bodyJson(const BodySpec& b) {
  const Mat3& J = b.inertia;
  json o = {{"name", b.name}, {"parent", b.parent}, {"mass", b.mass},
            {"inertia", {J(0, 0), J(1, 1), J(2, 2), J(0, 1), J(0, 2), J(1, 2)}}, {"joint", jointJson(b.joint)}};
  o.update(b.extra);
  return o;
}

}  // namespace

std::string sceneJson(const SceneSpec& s) {
  json head = {{"format", "eigenmass-scene/1"}, {"name", s.name}, {"gravity", vecJson(s.gravity)}};
  head.update(s.extra);
  std::string text = "{\n";
  for (auto it = head.begin(); it != head.end(); ++it) text += "  " + json(it.key()).dump() + ": " + it.value().dump() + ",\n";
  text += "  \"bodies\": [\n";
  for (size_t i = 0; i < s.bodies.size(); ++i)
    text += "    " + bodyJson(s.bodies[i]).dump() + (i + 1 < s.bodies.size() ? ",\n" : "\n");
  text += "  ],\n" + listText("loops", s.loops, loopJson) + listText("forces", s.forces, forceJson);
  json sim = {{"t_end", s.t_end}, {"output_dt", s.output_dt}};
  if (s.assemble) sim["assemble"] = true;
  text += "  \"simulate\": " + sim.dump();
  if (s.benchmark) text += ",\n  \"benchmark\": " + benchmarkJson(*s.benchmark).dump();
  text += "\n}\n";
  return text;
}

Model buildModel(const SceneSpec& spec, Assembly* assembled) {
  const int n = static_cast<int>(spec.bodies.size());
  if (n == 0) throw Err("bodies", "empty body list");
  requireMemoryFor(spec.bodies);
  // Parents are named in the file: "ground" is the format's word for the base.
  std::unordered_map<std::string, int> by_name;
  for (int f = 0; f < n; ++f) {
    const std::string& name = spec.bodies[f].name;
    if (name == "ground") throw Err(bodyPath(f, "name"), "'ground' is reserved");
    by_name.emplace(name, f);  // the first of duplicates; buildModel rejects the rest
  }
  std::vector<BodyDef> defs(n);
  for (int f = 0; f < n; ++f) {
    const BodySpec& b = spec.bodies[f];
    defs[f] = {b.name, -1, b.mass, b.inertia, b.joint};
    if (b.parent == "ground") continue;
    auto it = by_name.find(b.parent);
    if (it == by_name.end()) throw Err(bodyPath(f, "parent"), "unknown parent '" + printable(b.parent, 40) + "'");
    defs[f].parent = it->second;
  }
  const auto end = [&by_name](const std::string& body, const std::string& path) {
    if (body == "ground") return -1;
    auto it = by_name.find(body);
    if (it == by_name.end()) throw Err(path, "unknown body '" + printable(body, 40) + "'");
    return it->second;
  };
  MechanismDef mech;
  for (size_t i = 0; i < spec.loops.size(); ++i) {
    const LoopSpec& l = spec.loops[i];
    const std::string path = at("loops", i);
    mech.loops.push_back({l.name, l.type, {end(l.body_a, at(path, "body_a")), l.point_a}, {end(l.body_b, at(path, "body_b")), l.point_b},
                          l.axis_a, l.axis_b, Mat3::Identity()});
    // A copy of a closure adds only redundant rows (the doubtful list of issue 73: 3000 copies of one
    // loop loaded, 1000 cost 1.8 s per step and dense scratch of rows^2): refused, naming the first.
    const Loop& now = mech.loops.back();
    const auto same = [](const Attachment& x, const Attachment& y) { return x.body == y.body && x.point == y.point; };
    for (size_t j = 0; j < i; ++j) {
      const Loop& was = mech.loops[j];
      const bool ends = (same(now.a, was.a) && same(now.b, was.b) && now.axis_a == was.axis_a && now.axis_b == was.axis_b) ||
                        (now.type == LoopType::Ball && same(now.a, was.b) && same(now.b, was.a));
      if (now.type == was.type && ends)
        throw Err(path, "the same closure as " + at("loops", j) + " ('" + was.name + "'): a copy adds only redundant rows");
    }
  }
  for (size_t i = 0; i < spec.forces.size(); ++i) {
    const ForceSpec& f = spec.forces[i];
    const std::string path = at("forces", i);
    mech.springs.push_back({f.name, {end(f.body_a, at(path, "body_a")), f.point_a}, {end(f.body_b, at(path, "body_b")), f.point_b},
                            f.k, f.c, f.length});
  }
  Model m;
  try {
    m = em::buildModel(spec.name, spec.gravity, defs, mech);
  } catch (const ModelError& e) {
    throw Err(bodyPath(e.index, e.field), e.detail);
  }
  checkMechanismStart(m, spec.assemble, assembled);
  return m;
}

}  // namespace em
