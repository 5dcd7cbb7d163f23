#include "outside/plugin.hpp"

#include <dlfcn.h>

#include <cmath>
#include <deque>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "io/digest.hpp"
#include "io/json_input.hpp"
#include "io/scene_json.hpp"
#include "io/trajectory_json.hpp"
#include "outside/eigenmass_plugin.h"
#include "outside/isolate.hpp"
#include "solver/formation.hpp"
#include "solver/integrate.hpp"
#include "solver/applied_forces.hpp"
#include "solver/mechanism/constrained.hpp"
#include "solver/text.hpp"

namespace em {

// The C header's joint kinds are JointType's, value for value, and every kind
// is named there: a kind added to one and not the other fails to compile.
constexpr bool pluginKindsMatch() {
  constexpr int c[] = {EM_REVOLUTE, EM_UNIVERSAL, EM_GIMBAL, EM_BALL, EM_PRISMATIC, EM_FREE, EM_PLANAR};
  constexpr JointType t[] = {JointType::Revolute, JointType::Universal, JointType::Gimbal, JointType::Ball,
                             JointType::Prismatic, JointType::Free, JointType::Planar};
  for (int k = 0; k < EM_JOINT_KINDS; ++k)
    if (c[k] != static_cast<int>(t[k]) || kJointTypes[k].type != t[k]) return false;
  return std::size(kJointTypes) == EM_JOINT_KINDS && std::size(c) == EM_JOINT_KINDS;
}
static_assert(pluginKindsMatch(), "outside/eigenmass_plugin.h's em_joint_kind must name every JointType, in its order");

namespace {

using AbiFn = int (*)();
using CreateFn = void* (*)(const em_model*, char*, size_t);
using UdotFn = int (*)(void*, double, const double*, const double*, const double*, double*, char*, size_t);
using DestroyFn = void (*)(void*);

// One loaded library (a row's `make` finds it by the row's id).
struct PluginLib {
  Method id;
  std::string name, path, sha256, summary;
  void* handle = nullptr;
  CreateFn create = nullptr;
  UdotFn udot = nullptr;
  DestroyFn destroy = nullptr;
};

std::deque<PluginLib>& libs() {
  static std::deque<PluginLib> table;  // addresses never change: rows point at `summary`
  return table;
}

const PluginLib* findLib(Method id) {
  for (const PluginLib& l : libs())
    if (l.id == id) return &l;
  return nullptr;
}

double g_timeout = kPluginTimeout;

// The model as the ABI hands it (em_model), with the storage it points into.
class AbiModel {
 public:
  explicit AbiModel(const Model& m) : name_(m.name), json_(sceneJson(specOf(m))) {
    bodies_.reserve(m.bodies.size());
    for (const Body& b : m.bodies) bodies_.push_back(bodyOf(b));
    int drives = 0;
    for (const Body& b : m.bodies) drives += b.joint.torque.size() > 0;
    model_ = {EM_PLUGIN_ABI, name_.c_str(), m.n(), m.nq, m.nu, {m.gravity.x(), m.gravity.y(), m.gravity.z()},
              bodies_.data(), json_.c_str(), static_cast<int>(m.loops.size()), static_cast<int>(m.point_springs.size()), drives};
  }
  AbiModel(const AbiModel&) = delete;
  AbiModel& operator=(const AbiModel&) = delete;
  const em_model* get() const { return &model_; }

 private:
  static SceneSpec specOf(const Model& m) {
    SceneSpec s;
    s.name = m.name;
    s.gravity = m.gravity;
    for (const Body& b : m.bodies)
      s.bodies.push_back({b.name, b.parent < 0 ? "ground" : m.bodies[b.parent].name, b.mass, b.J, b.joint, nlohmann::json::object()});
    return s;
  }

  static em_body bodyOf(const Body& b) {
    em_body e{};
    e.name = b.name.c_str();
    e.parent = b.parent;
    e.joint = static_cast<int>(b.joint.type);
    e.iq = b.iq, e.nq = b.nq(), e.iu = b.iu, e.nu = b.nu();
    e.mass = b.mass;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) e.inertia[3 * r + c] = b.J(r, c);
    for (int k = 0; k < jointAxes(b.joint.type); ++k)  // a kind's unused axes stay zero (gimbal, ball, free: none)
      for (int c = 0; c < 3; ++c) e.axis[k][c] = b.joint.axis[k][c];
    for (int c = 0; c < 3; ++c) e.in_parent[c] = b.joint.in_parent[c], e.in_body[c] = b.joint.in_body[c];
    if (b.joint.has_spring) {
      e.spring_k = b.joint.spring.k.data();
      e.spring_c = b.joint.spring.c.data();
      e.spring_rest = b.joint.spring.q_rest.data();
    }
    return e;
  }

  std::string name_, json_;
  std::vector<em_body> bodies_;
  em_model model_;
};

// "lib.so: create: <its message>" from an error buffer that may be unterminated or empty.
std::string said(const char* err, size_t size) {
  const std::string s(err, strnlen(err, size));
  return s.empty() ? "(no message)" : printable(s, 200);  // its bytes escaped: a newline or ESC stays on our one line
}

// A plugin's method on one model: the tree's u' from (t, q, u) and tau. On a
// mechanism tau carries the drives' and point springs' generalized forces,
// and A^-1 X (the multipliers' A^-1 G^T) comes from the same plugin by its
// linearity in tau (eigenmass_plugin.h): the loops are closed around its u'.
class PluginMethod final : public MethodImpl {
 public:
  PluginMethod(const Model& m, const PluginLib& lib)
      : lib_(lib), abi_(m), m_(m), tau_(Eigen::VectorXd::Zero(m.nu)), tau_x_(m.nu), base_(m.nu), col_(m.nu),
        q_(m.nq), u_(m.nu), diag_(m.nu), inv_(m.isMechanism() ? m.nu : 0, m.isMechanism() ? m.nu : 0), eye_(inv_.rows(), inv_.cols()),
        llt_(inv_.rows()) {
    eye_.setIdentity();
    char err[512] = "";
    self_ = lib.create(abi_.get(), err, sizeof err);
    if (!self_) throw std::runtime_error("em_plugin_create returned NULL: " + said(err, sizeof err));
  }
  ~PluginMethod() override { lib_.destroy(self_); }
  // A tree's u' needs nothing formed; a mechanism's tau needs the kinematics
  // (Dynamics forms them, and A, for a mechanism whatever the method says).
  bool needsEquations() const override { return false; }
  bool needsKinematics() const override { return m_.isMechanism(); }
  bool needsA() const override { return false; }

  Status rates(double t, const double* q, const double* u, const Workspace& ws, const double*, double* udot, double*,
               EvalInfo&) override {
    isolatedBeat(t);
    if (m_.isMechanism() || m_.has_control) {  // a joint controller's torques: ws.control, set by Dynamics
      tau_.setZero();
      addMechanismForces(m_, ws, tau_);
    }
    if (!call(t, q, u, tau_.data(), udot)) return Status::failure(t, Failure::Plugin, failure_);
    if (!m_.loops.empty()) {  // where solveWithA differentiates
      t_ = t;
      q_ = Eigen::Map<const Eigen::VectorXd>(q, m_.nq);
      u_ = Eigen::Map<const Eigen::VectorXd>(u, m_.nu);
      base_ = Eigen::Map<const Eigen::VectorXd>(udot, m_.nu);
      diag_ = ws.A.diagonal();  // formed: Dynamics forms A where loops are
    }
    return {};
  }

  // out = A^-1 X column by column: u'(tau + s x) - u'(tau) = s A^-1 x, at the
  // state of the last rates(). s is a power of two (an exact division) that
  // makes s A^-1 x about as large as u' itself, so the difference keeps its
  // digits; the size of A^-1 x is judged from the diagonal of the A that
  // Dynamics formed (only the scale, never the value, comes from it).
  bool hasOwnInverse() const override { return true; }
  bool solveWithA(const double*, const Eigen::MatrixXd& X, Eigen::MatrixXd& out) override {
    failure_.clear();
    const double size = std::max(base_.cwiseAbs().maxCoeff(), 1.0);
    for (Eigen::Index j = 0; j < X.cols(); ++j) {
      double guess = 0;
      for (Eigen::Index i = 0; i < X.rows(); ++i) guess = std::max(guess, std::abs(X(i, j)) / diag_(i));
      const double s = guess > 0 && std::isfinite(guess) ? std::exp2(std::round(std::log2(size / guess))) : 1.0;
      tau_x_ = tau_ + s * X.col(j);
      const bool answered = call(t_, q_.data(), u_.data(), tau_x_.data(), col_.data());
      if (answered && !col_.allFinite()) failure_ = "plugin '" + lib_.name + "': u' not finite (NaN or Inf) at tau + a row of G^T";
      if (!answered || !failure_.empty()) {
        out.setConstant(std::numeric_limits<double>::quiet_NaN());
        return true;
      }
      out.col(j) = (col_ - base_) / s;
    }
    return true;
  }
  // M = L, L L^T = A^-1 (A^-1 from the plugin as above, symmetrized).
  bool inverseSquareRoot(const double* x, Eigen::MatrixXd& M) override {
    solveWithA(x, eye_, inv_);
    for (Eigen::Index i = 0; i < inv_.rows(); ++i)  // symmetrized in place (no temporary per evaluation)
      for (Eigen::Index j = i + 1; j < inv_.cols(); ++j) inv_(i, j) = inv_(j, i) = 0.5 * (inv_(i, j) + inv_(j, i));
    llt_.compute(inv_);
    if (llt_.info() != Eigen::Success) M.setConstant(std::numeric_limits<double>::quiet_NaN());
    else M = llt_.matrixL();
    return true;
  }
  std::string solveFailure() const override { return failure_; }

 private:
  bool call(double t, const double* q, const double* u, const double* tau, double* udot) {
    char err[512] = "";
    if (lib_.udot(self_, t, q, u, tau, udot, err, sizeof err) == 0) return true;
    failure_ = "plugin '" + lib_.name + "': " + said(err, sizeof err);
    return false;
  }

  const PluginLib& lib_;
  AbiModel abi_;
  const Model& m_;
  void* self_ = nullptr;
  Eigen::VectorXd tau_, tau_x_, base_, col_, q_, u_, diag_;  // declared in the initializers' order
  Eigen::MatrixXd inv_, eye_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  double t_ = 0;
  std::string failure_;
};

std::unique_ptr<MethodImpl> makePluginMethod(const Model& m, const MethodInfo& row, const MethodOptions&) {
  const PluginLib* lib = findLib(row.id);
  if (!lib) throw std::logic_error("plugin: a row without its library");
  return std::make_unique<PluginMethod>(m, *lib);
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot read the plugin");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

template <class F>
F symbol(void* handle, const std::string& path, const char* name) {
  void* p = dlsym(handle, name);
  if (!p)
    throw std::invalid_argument(path + ": no symbol " + name + " (a plugin exports em_plugin_abi, em_plugin_create, "
                                "em_plugin_udot and em_plugin_destroy with C linkage; docs/plugins.md)");
  return reinterpret_cast<F>(p);
}

}  // namespace

std::pair<std::string, std::string> splitNamedFile(const std::string& option, const std::string& v) {
  const size_t eq = v.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == v.size())
    throw std::invalid_argument(option + ": '" + v + "': NAME=FILE expected (e.g. " + option + " mine=" +
                                (option == "--run" ? "run.csv" : "./libmine.so") + ")");
  return {v.substr(0, eq), v.substr(eq + 1)};
}

Method addPlugin(const std::string& name, const std::string& path) {
  for (const PluginLib& l : libs())
    if (l.name == name && l.path == path) return l.id;
  if (!isSceneName(name))
    throw std::invalid_argument("plugin name '" + printable(name, 40) + "': letters, digits, '_' and '-', 1 to 64 of them");
  Method taken;
  if (findMethod(name, taken)) throw std::invalid_argument("plugin name '" + printable(name, 40) + "': a method of that name exists");
  const std::string bytes = fileBytes(path);
  // A path without '/' would make dlopen search the library path: the file named is the one loaded.
  const std::string where = path.find('/') == std::string::npos ? "./" + path : path;
  void* handle = dlopen(where.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) throw std::invalid_argument(path + ": not a loadable library: " + dlerror());
  PluginLib lib;
  lib.name = name, lib.path = path, lib.sha256 = sha256Hex(bytes), lib.handle = handle;
  const AbiFn abi = symbol<AbiFn>(handle, path, "em_plugin_abi");
  lib.create = symbol<CreateFn>(handle, path, "em_plugin_create");
  lib.udot = symbol<UdotFn>(handle, path, "em_plugin_udot");
  lib.destroy = symbol<DestroyFn>(handle, path, "em_plugin_destroy");
  if (const int v = abi(); v != EM_PLUGIN_ABI)
    throw std::invalid_argument(path + ": built against plugin ABI " + std::to_string(v) + ", this eigenmass speaks " +
                                std::to_string(EM_PLUGIN_ABI) + " (rebuild it against its eigenmass_plugin.h)");
  lib.summary = "plugin " + path + ": its own u' under the in-house integrators";
  libs().push_back(lib);
  PluginLib& row = libs().back();
  MethodInfo added;
  added.name = row.name.c_str();
  added.make = makePluginMethod;
  added.summary = row.summary.c_str();
  added.isolated = true;
  // Not tree_only: on a mechanism the formulation closes the loops around its u' (PluginMethod).
  row.id = addMethod(added);
  return row.id;
}

bool isPlugin(Method method) { return findLib(method) != nullptr; }

void setPluginTimeout(double seconds) { g_timeout = seconds; }
double pluginTimeout() { return g_timeout; }

nlohmann::json pluginSource(Method method) {
  const PluginLib* lib = findLib(method);
  if (!lib) return nullptr;
  return {{"plugin", lib->path}, {"sha256", lib->sha256}, {"abi", EM_PLUGIN_ABI}, {"isolation", "child process"},
          {"timeout_s", g_timeout}};
}

namespace {

// Whether the child died (a crash, a hang) rather than returned or threw.
bool died(const Isolated& r) { return r.failure.rfind("crashed", 0) == 0 || r.failure.rfind("no return", 0) == 0; }

// What a plugin's failure in a child says: where a crash or a hang happened;
// what the plugin or the harness said otherwise.
std::string failureAt(const Isolated& r, const std::string& where) {
  if (!died(r)) return r.failure;
  return r.failure + (r.beat ? " in em_plugin_udot at t = " + gnum(r.t, 10) : " in em_plugin_create") + where +
         (r.failure.rfind("no return", 0) == 0 ? " (--plugin-timeout)" : "");
}

}  // namespace

namespace {

// The plugin's u' at (q, u) at t = 0, and on a mechanism the constrained one:
// the loops closed around it with no stabilization (eq. (M7)), as compare's
// crosscheck takes the in-house u'.
Status constrainedRates(const Model& m, PluginMethod& f, const Eigen::VectorXd& q, const Eigen::VectorXd& u, Eigen::VectorXd& udot) {
  Workspace ws(m);
  if (m.isMechanism()) formEquations(m, q.data(), u.data(), ws);
  EvalInfo info;
  const Status s = f.rates(0, q.data(), u.data(), ws, nullptr, udot.data(), nullptr, info);
  if (!s || m.loops.empty()) return s;
  LoopState ls(m);
  formLoops(m, ws, u.data(), ls);
  Eigen::MatrixXd AinvGt(m.nu, m.loop_rows);
  f.solveWithA(nullptr, ls.G.transpose(), AinvGt);
  if (!AinvGt.allFinite())
    return Status::failure(0, Failure::Plugin, f.solveFailure().empty() ? "A^-1 G^T from the plugin's u' is not finite" : f.solveFailure());
  ConstrainedSolve(m).solve(ls, AinvGt, 0.0, 0.0, udot);
  return s;
}

}  // namespace

void probePlugin(Method method, const Model& m) {
  const PluginLib* lib = findLib(method);
  if (!lib) throw std::logic_error("probePlugin: not a plugin");
  const Isolated r = runIsolated([&]() -> std::string {
    PluginMethod f(m, *lib);
    Eigen::VectorXd q = m.q0(), u = m.u0(), udot = Eigen::VectorXd::Zero(m.nu);
    const Status s = constrainedRates(m, f, q, u, udot);
    if (!s) throw std::runtime_error("em_plugin_udot returned an error at the initial state: " + s.cause);
    if (!udot.allFinite()) throw std::runtime_error("u' at the initial state is not finite (NaN or Inf)");
    return "";
  }, g_timeout);
  if (r.ok) return;
  throw std::invalid_argument(lib->path + ": " + failureAt(r, ", at the initial state of " + m.name));
}

Trajectory simulateIsolated(const Model& m, const CheckedRunSpec& checked_spec, const SampleObserver& observe) {
  const RunSpec& spec = checked_spec;
  const auto run = [&](const CheckedRunSpec& s) {
    return runIsolated([&] { return trajectoryJson(simulate(m, s, observe)).dump(); }, g_timeout);
  };
  const Isolated r = run(checked_spec);
  if (r.ok) return trajectoryFromJson(nlohmann::json::parse(r.output), spec, "a plugin's run");
  // Crashed or hung: the samples before it, from the same run repeated up to the last output time before r.t.
  const std::string name = methodName(spec.method);
  RunSpec cut = spec;
  // The last output time strictly before r.t: the repeated run's last evaluation is at its t_end.
  cut.t_end = (std::ceil(r.t / spec.output_dt * (1 - 1e-12)) - 1) * spec.output_dt;
  Trajectory tr = makeTrajectory(m, spec);
  if (cut.t_end >= spec.output_dt) {
    const Isolated again = run(checked(cut));  // a shorter run of a checked spec: t_end a whole multiple of output_dt
    if (again.ok) {
      tr = trajectoryFromJson(nlohmann::json::parse(again.output), cut, "a plugin's run");
      tr.run = spec;
    }
  }
  if (tr.size() == 0) {
    Workspace ws(m);
    const Eigen::VectorXd q = m.q0(), u = m.u0();
    appendStateSample(tr, m, ws, 0, q.data(), u.data(), 0);
  }
  markFailed(tr, r.t, Failure::Plugin, "plugin '" + name + "' " + failureAt(r, ""));
  return tr;
}

std::vector<Eigen::VectorXd> pluginUdots(Method method, const Model& m, const std::vector<Eigen::VectorXd>& q,
                                         const std::vector<Eigen::VectorXd>& u) {
  const PluginLib* lib = findLib(method);
  if (!lib) throw std::logic_error("pluginUdots: not a plugin");
  const Isolated r = runIsolated([&] {
    PluginMethod f(m, *lib);
    nlohmann::json out = nlohmann::json::array();
    Eigen::VectorXd udot(m.nu);
    for (size_t k = 0; k < q.size(); ++k) {
      const Status s = constrainedRates(m, f, q[k], u[k], udot);
      if (!s) throw std::runtime_error("em_plugin_udot returned an error at state " + std::to_string(k) + ": " + s.cause);
      out.push_back(std::vector<double>(udot.data(), udot.data() + m.nu));
    }
    return out.dump();
  }, g_timeout);
  if (!r.ok) throw std::runtime_error(lib->path + ": " + failureAt(r, ""));
  std::vector<Eigen::VectorXd> out;
  for (const auto& v : nlohmann::json::parse(r.output)) {
    const std::vector<double> x = v.get<std::vector<double>>();
    out.push_back(Eigen::Map<const Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())));
  }
  return out;
}

}  // namespace em
