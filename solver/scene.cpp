#include "solver/scene.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

namespace em {

namespace {

using json = nlohmann::json;

// Relative tolerance of the inertia checks: equality in the triangle
// inequalities (a thin plate) must pass despite rounding of written decimals.
constexpr double kInertiaRelTol = 1e-9;
// Universal axes count as perpendicular when |cos| is below this (scene-format.md).
constexpr double kPerpendicularTol = 1e-9;

std::string at(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}
std::string at(const std::string& path, size_t i) { return path + "[" + std::to_string(i) + "]"; }

// Every key must be known for its object; "x-" keys are free.
void checkKeys(const json& obj, const std::string& path, std::initializer_list<const char*> known) {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string& k = it.key();
    if (k.rfind("x-", 0) == 0) continue;
    bool ok = false;
    for (const char* kk : known) ok = ok || k == kk;
    if (!ok) throw SceneError(at(path, k), "unknown key");
  }
}

const json& require(const json& obj, const std::string& path, const char* key) {
  auto it = obj.find(key);
  if (it == obj.end()) throw SceneError(at(path, key), "missing required key");
  return *it;
}

double number(const json& v, const std::string& path) {
  if (!v.is_number()) throw SceneError(path, "expected a number, got " + std::string(v.type_name()) + " " + v.dump());
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw SceneError(path, "not a finite number");
  return x;
}

std::string string(const json& v, const std::string& path) {
  if (!v.is_string()) throw SceneError(path, "expected a string, got " + std::string(v.type_name()));
  return v.get<std::string>();
}

Eigen::VectorXd numbers(const json& v, const std::string& path, int min_len, int max_len = -1) {
  if (max_len < 0) max_len = min_len;
  if (!v.is_array()) throw SceneError(path, "expected a list of numbers");
  const int len = static_cast<int>(v.size());
  if (len < min_len || len > max_len)
    throw SceneError(path, "expected " + std::to_string(min_len) +
                               (max_len != min_len ? " or " + std::to_string(max_len) : "") +
                               (max_len == 1 ? " number" : " numbers") + ", got " + std::to_string(len));
  Eigen::VectorXd x(len);
  for (int i = 0; i < len; ++i) x[i] = number(v[i], at(path, i));
  return x;
}

Vec3 vec3(const json& v, const std::string& path) { return numbers(v, path, 3); }

Vec3 unitAxis(const json& v, const std::string& path) {
  const Vec3 a = vec3(v, path);
  if (!(a.norm() > 0)) throw SceneError(path, "zero axis");
  return a.normalized();
}

Mat3 inertia(const json& v, const std::string& path) {
  const Eigen::VectorXd x = numbers(v, path, 3, 6);
  if (x.size() != 3 && x.size() != 6) throw SceneError(path, "expected 3 or 6 numbers");
  Mat3 J = x.head<3>().asDiagonal();
  if (x.size() == 6) {
    J(0, 1) = J(1, 0) = x[3];
    J(0, 2) = J(2, 0) = x[4];
    J(1, 2) = J(2, 1) = x[5];
  }
  const Vec3 I = Eigen::SelfAdjointEigenSolver<Mat3>(J).eigenvalues();  // ascending
  const double scale = I.cwiseAbs().maxCoeff();
  if (!(I[0] > kInertiaRelTol * scale) || !(scale > 0))
    throw SceneError(path, "not positive definite (principal moments " + std::to_string(I[0]) + ", " +
                               std::to_string(I[1]) + ", " + std::to_string(I[2]) + ")");
  if (I[0] + I[1] < I[2] * (1 - kInertiaRelTol))
    throw SceneError(path, "violates the triangle inequality (principal moments " + std::to_string(I[0]) +
                               " + " + std::to_string(I[1]) + " < " + std::to_string(I[2]) + ")");
  return J;
}

JointType jointType(const json& v, const std::string& path) {
  const std::string t = string(v, path);
  for (JointType k : {JointType::Revolute, JointType::Universal, JointType::Gimbal, JointType::Ball})
    if (t == jointTypeName(k)) return k;
  throw SceneError(path, "unknown joint type '" + t + "' (revolute, universal, gimbal, ball)");
}

// k or c: one number for every coordinate, or one per coordinate; >= 0.
Eigen::VectorXd perCoordinate(const json& v, const std::string& path, int nu) {
  Eigen::VectorXd x = v.is_array() ? numbers(v, path, nu) : Eigen::VectorXd::Constant(nu, number(v, path));
  for (int i = 0; i < nu; ++i)
    if (x[i] < 0) throw SceneError(v.is_array() ? at(path, i) : path, "must be >= 0");
  return x;
}

Spring spring(const json& v, const std::string& path, int nu) {
  if (!v.is_object()) throw SceneError(path, "expected an object {k, c, q_rest}");
  checkKeys(v, path, {"k", "c", "q_rest"});
  Spring s;
  s.k = v.contains("k") ? perCoordinate(v["k"], at(path, "k"), nu) : Eigen::VectorXd::Zero(nu);
  s.c = v.contains("c") ? perCoordinate(v["c"], at(path, "c"), nu) : Eigen::VectorXd::Zero(nu);
  s.q_rest = v.contains("q_rest") ? numbers(v["q_rest"], at(path, "q_rest"), nu) : Eigen::VectorXd::Zero(nu);
  return s;
}

Joint joint(const json& v, const std::string& path) {
  if (!v.is_object()) throw SceneError(path, "expected an object");
  Joint j;
  j.type = jointType(require(v, path, "type"), at(path, "type"));
  const std::string kind = jointTypeName(j.type);
  checkKeys(v, path, {"type", "axis", "axes", "in_parent", "in_body", "q0", "u0", "spring"});
  // Keys that belong to another joint kind are errors (scene-format.md).
  auto forbid = [&](const char* key, bool allowed) {
    if (!allowed && v.contains(key)) throw SceneError(at(path, key), std::string("not allowed on a ") + kind + " joint");
  };
  forbid("axis", j.type == JointType::Revolute);
  forbid("axes", j.type == JointType::Universal);
  forbid("spring", j.type != JointType::Ball);
  if (j.type == JointType::Revolute) j.axis[0] = unitAxis(require(v, path, "axis"), at(path, "axis"));
  if (j.type == JointType::Universal) {
    const std::string p = at(path, "axes");
    const json& a = require(v, path, "axes");
    if (!a.is_array() || a.size() != 2) throw SceneError(p, "expected two axes");
    j.axis[0] = unitAxis(a[0], at(p, 0));
    j.axis[1] = unitAxis(a[1], at(p, 1));
    if (std::abs(j.axis[0].dot(j.axis[1])) > kPerpendicularTol) throw SceneError(p, "axes are not perpendicular");
  }
  j.in_parent = vec3(require(v, path, "in_parent"), at(path, "in_parent"));
  j.in_body = vec3(require(v, path, "in_body"), at(path, "in_body"));
  const int nq = jointNq(j.type), nu = jointNu(j.type);
  if (v.contains("q0")) {
    j.q0 = numbers(v["q0"], at(path, "q0"), nq);
  } else {
    j.q0 = Eigen::VectorXd::Zero(nq);
    if (j.type == JointType::Ball) j.q0[0] = 1;
  }
  if (j.type == JointType::Ball) {
    if (!(j.q0.norm() > 0)) throw SceneError(at(path, "q0"), "zero quaternion");
    j.q0.normalize();
  }
  j.u0 = v.contains("u0") ? numbers(v["u0"], at(path, "u0"), nu) : Eigen::VectorXd::Zero(nu);
  if (v.contains("spring")) {
    j.has_spring = true;
    j.spring = spring(v["spring"], at(path, "spring"), nu);
  }
  return j;
}

BodySpec body(const json& v, const std::string& path) {
  if (!v.is_object()) throw SceneError(path, "expected an object");
  checkKeys(v, path, {"name", "parent", "mass", "inertia", "joint"});
  BodySpec b;
  b.name = string(require(v, path, "name"), at(path, "name"));
  b.parent = string(require(v, path, "parent"), at(path, "parent"));
  b.mass = number(require(v, path, "mass"), at(path, "mass"));
  if (!(b.mass > 0)) throw SceneError(at(path, "mass"), "must be > 0");
  b.inertia = inertia(require(v, path, "inertia"), at(path, "inertia"));
  b.joint = joint(require(v, path, "joint"), at(path, "joint"));
  return b;
}

// The parse callback tracks the JSON path of the value being read, so that
// parser-level failures (a number overflow such as 1e999) and duplicate keys
// (which nlohmann would silently resolve to the last) name their key.
struct PathTracker {
  struct Frame {
    explicit Frame(bool is_array) : array(is_array) {}
    bool array;
    long count = 0;   // completed elements of an array: the index of the one being read
    std::string key;  // current key of an object
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  std::string duplicate;

  std::string path() const {
    std::string p;
    for (const Frame& f : stack) {
      if (f.array) p += "[" + std::to_string(f.count) + "]";
      else if (!f.key.empty()) p += (p.empty() ? "" : ".") + f.key;
    }
    return p.empty() ? "(document)" : p;
  }
  // nlohmann emits `value` only for primitives; a container completes at its end event.
  void completed() {
    if (!stack.empty() && stack.back().array) ++stack.back().count;
  }
  bool operator()(int, json::parse_event_t ev, json& parsed) {
    using E = json::parse_event_t;
    switch (ev) {
      case E::object_start: stack.emplace_back(false); break;
      case E::array_start: stack.emplace_back(true); break;
      case E::object_end:
      case E::array_end: stack.pop_back(); completed(); break;
      case E::key:
        stack.back().key = parsed.get<std::string>();
        if (!stack.back().keys.insert(stack.back().key).second && duplicate.empty()) duplicate = path();
        break;
      case E::value: completed(); break;
    }
    return true;
  }
};

json parseStrict(const std::string& text, PathTracker& tracker) {
  json doc = json::parse(text, [&tracker](int depth, json::parse_event_t ev, json& parsed) {
    return tracker(depth, ev, parsed);
  });
  if (!tracker.duplicate.empty()) throw SceneError(tracker.duplicate, "duplicate key");
  return doc;
}

std::string lineColumn(const std::string& text, size_t byte) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') { ++line; col = 1; } else { ++col; }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

SceneSpec spec(const json& doc) {
  if (!doc.is_object()) throw SceneError("(document)", "expected a JSON object");
  checkKeys(doc, "", {"format", "name", "gravity", "bodies", "simulate"});
  const std::string fmt = string(require(doc, "", "format"), "format");
  if (fmt != "eigenmass-scene/1") throw SceneError("format", "unsupported format '" + fmt + "' (expected eigenmass-scene/1)");
  SceneSpec s;
  s.name = string(require(doc, "", "name"), "name");
  if (s.name.empty()) throw SceneError("name", "empty name");
  if (doc.contains("gravity")) s.gravity = vec3(doc["gravity"], "gravity");
  const json& bodies = require(doc, "", "bodies");
  if (!bodies.is_array()) throw SceneError("bodies", "expected a list of bodies");
  if (bodies.empty()) throw SceneError("bodies", "empty body list");
  for (size_t i = 0; i < bodies.size(); ++i) s.bodies.push_back(body(bodies[i], at("bodies", i)));
  if (doc.contains("simulate")) {
    const json& sim = doc["simulate"];
    if (!sim.is_object()) throw SceneError("simulate", "expected an object");
    checkKeys(sim, "simulate", {"t_end", "output_dt"});
    if (sim.contains("t_end")) s.t_end = number(sim["t_end"], "simulate.t_end");
    if (!(s.t_end > 0)) throw SceneError("simulate.t_end", "must be > 0");
    if (sim.contains("output_dt")) s.output_dt = number(sim["output_dt"], "simulate.output_dt");
    if (!(s.output_dt > 0)) throw SceneError("simulate.output_dt", "must be > 0");
  }
  return s;
}

}  // namespace

SceneSpec parseSceneSpec(const std::string& text, const std::string& source) {
  try {
    json doc;
    PathTracker tracker;
    try {
      doc = parseStrict(text, tracker);
    } catch (const json::parse_error& e) {
      throw SceneError("(document)", "invalid JSON at " + lineColumn(text, e.byte));
    } catch (const json::exception& e) {
      // out_of_range.406: a number too large for a double (1e999), at the tracked path.
      const std::string w = e.what();
      throw SceneError(tracker.path(), w.substr(w.find(']') + 2) + " (not a finite number)");
    }
    return spec(doc);
  } catch (const SceneError& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
}

Model loadSceneText(const std::string& text, const std::string& source) {
  const SceneSpec s = parseSceneSpec(text, source);
  try {
    return buildModel(s);
  } catch (const SceneError& e) {
    throw std::runtime_error(source + ": " + e.what());
  }
}

Model loadScene(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open the scene file");
  std::stringstream buf;
  buf << in.rdbuf();
  return loadSceneText(buf.str(), path);
}

}  // namespace em
