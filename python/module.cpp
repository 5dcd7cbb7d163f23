// The Python module `eigenmass` (docs/python.md): scenes, the equations at any
// state from any engine that gives them, runs, comparisons (the same report
// as `compare --out`) and a Python function as a method. Everything is the
// library the CLI runs; errors are Python exceptions carrying the CLI's line.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <deque>
#include <filesystem>
#include <map>
#include <optional>

#include "compare/comparison.hpp"
#include "compare/engines.hpp"
#include "compare/report.hpp"
#include "io/csv.hpp"
#include "compare/provenance.hpp"
#include "io/json_input.hpp"
#include "io/run_spec_json.hpp"
#include "io/scene_json.hpp"
#include "outside/plugin.hpp"
#include "outside/recorded.hpp"
#include "reference/engine.hpp"
#include "solver/formation.hpp"
#include "solver/integrate.hpp"
#include "solver/mechanism/formulation.hpp"
#include "solver/method.hpp"

namespace py = pybind11;
using namespace em;

namespace {

py::array_t<double> vec(const Eigen::VectorXd& v) {
  py::array_t<double> a(v.size());
  std::copy(v.data(), v.data() + v.size(), a.mutable_data());
  return a;
}

py::array_t<double> mat(const Eigen::MatrixXd& A) {
  py::array_t<double> a({A.rows(), A.cols()});
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    for (Eigen::Index j = 0; j < A.cols(); ++j) a.mutable_at(i, j) = A(i, j);
  return a;
}

// Rows of per-sample vectors as one (samples x n) array.
py::array_t<double> rows(const std::vector<Eigen::VectorXd>& v, Eigen::Index n) {
  py::array_t<double> a({static_cast<Eigen::Index>(v.size()), n});
  for (size_t k = 0; k < v.size(); ++k)
    for (Eigen::Index i = 0; i < n; ++i) a.mutable_at(k, i) = v[k][i];
  return a;
}

// A numpy vector of `n` numbers in the scene's (file) order, as the model's internal order.
Eigen::VectorXd internal(const py::array_t<double, py::array::c_style | py::array::forcecast>& a, long n, const char* what,
                         const std::vector<int>& perm) {
  if (a.ndim() != 1 || a.shape(0) != n)
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(n) + " numbers expected, in the scene's order");
  Eigen::VectorXd x(n);
  for (long k = 0; k < n; ++k) x[perm[k]] = a.at(k);
  if (!x.allFinite()) throw std::invalid_argument(std::string(what) + ": not finite");
  return x;
}

Eigen::VectorXd fileOrder(const Eigen::VectorXd& x, const std::vector<int>& perm) {
  Eigen::VectorXd f(x.size());
  for (Eigen::Index k = 0; k < x.size(); ++k) f[k] = x[perm[k]];
  return f;
}

py::object fromJson(const nlohmann::json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

// ---- a Python function as a method -----------------------------------------

std::map<Method, py::object*>& pythonFunctions() {
  static auto* table = new std::map<Method, py::object*>;  // never destroyed: it outlives the interpreter's objects
  return *table;
}

class PythonMethod final : public MethodImpl {
 public:
  PythonMethod(const Model& m, py::object f) : m_(m), f_(std::move(f)), pq_(m.qFilePermutation()), pu_(m.uFilePermutation()) {}
  bool needsEquations() const override { return false; }
  bool needsKinematics() const override { return false; }
  bool needsA() const override { return false; }
  Status rates(double t, const double* q, const double* u, const Workspace&, const double*, double* udot, double*,
               EvalInfo&) override {
    const Eigen::VectorXd qf = fileOrder(Eigen::Map<const Eigen::VectorXd>(q, m_.nq), pq_);
    const Eigen::VectorXd uf = fileOrder(Eigen::Map<const Eigen::VectorXd>(u, m_.nu), pu_);
    const std::string want = "not a vector of nu = " + std::to_string(m_.nu) + " numbers";
    try {
      const py::object r = f_(t, vec(qf), vec(uf));
      if (r.is_none()) return Status::failure(t, Failure::Plugin, "the Python method returned None, " + want);
      const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(r);
      if (!a) return Status::failure(t, Failure::Plugin, "the Python method returned a " + typeName(r) + ", " + want);
      if (a.ndim() != 1 || a.shape(0) != m_.nu)
        return Status::failure(t, Failure::Plugin, "the Python method returned " + shapeOf(r, a) + ", " + want);
      for (int k = 0; k < m_.nu; ++k) udot[pu_[k]] = a.at(k);
    } catch (py::error_already_set& e) {
      // Ctrl-C (KeyboardInterrupt) and sys.exit (SystemExit) are the user's, not the method's: they end the call.
      if (!e.matches(PyExc_Exception)) throw;
      return Status::failure(t, Failure::Plugin, std::string("the Python method raised: ") + e.what());
    }
    return {};
  }

 private:
  static std::string typeName(const py::handle& h) { return py::str(h.get_type().attr("__name__")).cast<std::string>(); }
  // "a float", "an array of shape (1, 1)": what came back, in Python's words.
  static std::string shapeOf(const py::handle& r, const py::array& a) {
    if (a.ndim() == 0) return "a " + typeName(r) + " (a scalar)";
    std::string s = "an array of shape (";
    for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
    return s + (a.ndim() == 1 ? ",)" : ")");
  }

  const Model& m_;
  py::object f_;
  std::vector<int> pq_, pu_;
};

std::unique_ptr<MethodImpl> makePythonMethod(const Model& m, const MethodInfo& row, const MethodOptions&) {
  return std::make_unique<PythonMethod>(m, *pythonFunctions().at(row.id));
}

// The methods from outside one call added (Python functions, plugins,
// recorded runs): they live as long as the call, so a name is free again
// after it and a probe that failed leaves nothing behind (methods()).
class CallMethods {
 public:
  CallMethods() = default;
  CallMethods(const CallMethods&) = delete;
  CallMethods& operator=(const CallMethods&) = delete;
  ~CallMethods() {
    for (Method m : added_) {
      retireMethod(m);
      if (auto it = pythonFunctions().find(m); it != pythonFunctions().end()) {
        delete it->second;  // the call holds the GIL: the function's reference is dropped here
        pythonFunctions().erase(it);
      }
    }
  }
  Method add(Method m) {
    added_.push_back(m);
    return m;
  }
  // The method `name` running f, for this call.
  Method function(const std::string& name, py::object f, const std::string& keyword) {
    if (!isSceneName(name))
      throw std::invalid_argument(keyword + ": the name '" + printable(name, 40) + "': letters, digits, '_' and '-', 1 to 64 of them");
    Method id;
    if (findMethod(name, id)) throw std::invalid_argument(keyword + ": the name '" + name + "' is a method's already");
    static std::deque<std::string> names;  // the rows point at them (a retired row's id still reads its name)
    names.push_back(name);
    MethodInfo row;
    row.name = names.back().c_str();
    row.make = makePythonMethod;
    row.summary = "a Python function f(t, q, u) -> u' (eigenmass.compare)";
    row.tree_only = true;  // f sees (t, q, u) alone: a tree's u'
    id = add(addMethod(row));
    pythonFunctions()[id] = new py::object(std::move(f));
    return id;
  }
  // "classical", or ("name", f): a method of the registry or a Python function.
  Method of(const py::handle& h, const char* keyword) {
    if (py::isinstance<py::str>(h)) return parseMethod(h.cast<std::string>());
    if (!py::isinstance<py::tuple>(h) || py::len(h) != 2 || !py::isinstance<py::str>(h.cast<py::tuple>()[0]) ||
        !PyCallable_Check(h.cast<py::tuple>()[1].ptr()))
      throw std::invalid_argument(std::string(keyword) + ": each a name or a pair (name, f) with f(t, q, u) -> u'");
    const auto t = h.cast<py::tuple>();
    return function(t[0].cast<std::string>(), py::reinterpret_borrow<py::object>(t[1]), keyword);
  }

 private:
  std::vector<Method> added_;
};

// ---- the functions ---------------------------------------------------------

// A path as Python gives it: a str or any os.PathLike (pathlib.Path), by os.fspath.
std::string pathArg(const py::handle& h, const char* keyword) {
  py::object p;
  try {
    p = py::module_::import("os").attr("fspath")(h);
  } catch (py::error_already_set&) {
    throw std::invalid_argument(std::string(keyword) + ": a path (str or os.PathLike) expected, got a " +
                                py::str(h.get_type().attr("__name__")).cast<std::string>());
  }
  if (!py::isinstance<py::str>(p)) throw std::invalid_argument(std::string(keyword) + ": a path as text expected, not bytes");
  return p.cast<std::string>();
}

// {"name": path}: the plugins= and runs= keywords.
std::vector<std::pair<std::string, std::string>> namedPaths(const py::dict& d, const char* keyword) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [k, v] : d) {
    if (!py::isinstance<py::str>(k)) throw std::invalid_argument(std::string(keyword) + ": names must be str");
    out.emplace_back(k.cast<std::string>(), pathArg(v, keyword));
  }
  return out;
}

Scene load(const py::object& path_arg, bool balance_inertia, const std::vector<std::string>& lock_joints, bool floating_base,
           bool assemble) {
  const std::string path = pathArg(path_arg, "path");
  UrdfOptions o;
  o.balance_inertia = balance_inertia;
  o.lock_joints = lock_joints;
  o.floating_base = floating_base;
  try {
    Scene s = loadScene(path, o, assemble);
    checkInitialState(s);
    return s;
  } catch (const std::exception& e) {
    // The import options' lines name the CLI's flags: name the keyword arguments instead.
    std::string what = e.what();
    for (const auto& [flag, keyword] : {std::pair<std::string, std::string>{"--balance-inertia", "balance_inertia"},
                                        {"--lock-joint", "lock_joints"}, {"--floating-base", "floating_base"},
                                        {"--assemble", "assemble"}})
      for (size_t at = what.find(flag); at != std::string::npos; at = what.find(flag, at + keyword.size()))
        what.replace(at, flag.size(), keyword);
    if (dynamic_cast<const std::invalid_argument*>(&e)) throw std::invalid_argument(what);
    throw std::runtime_error(what);
  }
}

py::dict equations(const Scene& s, const std::string& engine, std::optional<py::array_t<double>> q_in,
                   std::optional<py::array_t<double>> u_in) {
  const Model& m = s.model;
  const Engine e = parseEngine(engine);
  const Eigen::VectorXd q = q_in ? internal(*q_in, m.nq, "q", m.qFilePermutation()) : m.q0();
  const Eigen::VectorXd u = u_in ? internal(*u_in, m.nu, "u", m.uFilePermutation()) : m.u0();
  if (const std::string why = beyondStateBounds(m, q, u); !why.empty())  // the bounds a scene's q0 and u0 are held to
    throw std::invalid_argument(why);
  const Equations x = engineEquations(m, e, q, u);  // the CLI's equations, at this state
  py::dict d;
  d["engine"] = engine;
  d["A"] = mat(x.A);
  d["B"] = vec(x.B);
  d["udot"] = vec(x.udot);  // a mechanism's: the constrained u'
  d["eigenvalues"] = vec(x.eigenvalues);
  d["kinetic"] = x.kinetic, d["potential"] = x.potential, d["total"] = x.kinetic + x.potential;
  if (x.has_loops) {  // as the CLI's "loops": G (the scene's order), its rank, the gaps and the multipliers
    d["G"] = mat(x.G);
    d["rank"] = x.rank;
    d["g"] = vec(x.g);
    d["lambda"] = vec(x.lambda);
  }
  return d;
}

py::dict trajectoryDict(const Trajectory& tr) {
  py::dict d;
  d["method"] = tr.method(), d["integrator"] = tr.integrator();
  d["t"] = vec(Eigen::Map<const Eigen::VectorXd>(tr.t.data(), static_cast<Eigen::Index>(tr.t.size())));
  d["q"] = rows(tr.q, static_cast<Eigen::Index>(tr.q_names.size()));
  d["u"] = rows(tr.u, static_cast<Eigen::Index>(tr.u_names.size()));
  for (const auto& [key, v] : {std::pair<const char*, const std::vector<double>*>{"energy", &tr.energy},
                               {"kinetic", &tr.kinetic}, {"dissipated", &tr.dissipated}})
    d[key] = vec(Eigen::Map<const Eigen::VectorXd>(v->data(), static_cast<Eigen::Index>(v->size())));
  d["q_names"] = tr.q_names, d["u_names"] = tr.u_names;
  d["status"] = outcomeName(tr.status());
  d["failure"] = tr.failed() ? py::object(py::dict(py::arg("t") = tr.failure_time, py::arg("kind") = failureName(tr.failure_kind),
                                                   py::arg("cause") = tr.failure))
                             : py::object(py::none());
  d["steps"] = tr.steps, d["rhs_evals"] = tr.rhs_evals, d["run_time_s"] = tr.run_time_s;
  if (tr.has_loops) {  // a mechanism: the report's loops object, and per sample the CSV's loops.* and lambda.* columns
    d["loops"] = fromJson(loopsJson(tr, tr.run));
    const Eigen::Index n = static_cast<Eigen::Index>(tr.loop_samples.size()), m = static_cast<Eigen::Index>(tr.lambda_names.size());
    Eigen::MatrixXd violation(n, 4), lambda(n, m);
    for (Eigen::Index k = 0; k < n; ++k) {
      const LoopSample& l = tr.loop_samples[k];
      violation.row(k) << l.position_m, l.position_rad, l.velocity_m, l.velocity_rad;
      lambda.row(k) = l.lambda.transpose();
    }
    d["loop_violation"] = mat(violation);
    d["loop_violation_names"] = std::vector<std::string>(kLoopColumns.begin(), kLoopColumns.end());
    d["lambda"] = mat(lambda);
    d["lambda_names"] = tr.lambda_names;
  }
  return d;
}

// The in-house integrator and its step or tolerance as the CLI resolves them
// (a tolerance alone selects the engine's adaptive scheme; a step given to an
// adaptive scheme, or a tolerance to a fixed-step one, is refused).
void inHouseSettings(RunSpec& spec, Engine engine, const std::optional<std::string>& integrator, std::optional<double> dt,
                     std::optional<double> tol) {
  if (dt && tol) throw std::invalid_argument("dt and tol: one or the other");
  spec.integrator = integrator ? parseIntegrator(*integrator) : chosenIntegrator(engine, tol.has_value());
  if (dt) spec.dt = *dt;
  if (tol) spec.tol = *tol;
  const char* name = integratorName(spec.integrator);
  if (dt && !info(spec.integrator).fixed_step) throw std::invalid_argument("dt: " + std::string(name) + " takes a tolerance");
  if (tol && info(spec.integrator).fixed_step) throw std::invalid_argument("tol: " + std::string(name) + " takes a fixed step");
}

// The run settings as the CLI resolves them, checked once.
// formulation=: a table name on a scene with loops (the CLI's --formulation
// and its refusals, named as the keyword), into the loop options.
void applyFormulation(const Scene& s, const std::optional<std::string>& formulation, LoopOptions& loops) {
  if (!formulation) return;
  if (s.model.loops.empty()) throw std::invalid_argument("formulation: scene '" + s.model.name + "' has no loops");
  if (!findFormulation(*formulation, loops.formulation)) {
    std::vector<std::string> names;
    for (const FormulationInfo& f : formulationTable()) names.emplace_back(f.name);
    throw std::invalid_argument("formulation: '" + printable(*formulation, 40) + "' is not one of " + joined(names));
  }
}

CheckedRunSpec runSpec(const Scene& s, Method method, const std::optional<std::string>& integrator, std::optional<double> dt,
                       std::optional<double> tol, std::optional<double> t_end, std::optional<double> output_dt,
                       const std::optional<std::string>& formulation = std::nullopt) {
  RunSpec spec;
  spec.method = method;
  inHouseSettings(spec, spec.engine(), integrator, dt, tol);
  requireCompatible(spec.method, spec.integrator);
  applyFormulation(s, formulation, spec.options.loops);
  const RunSpec grid = onGrid(spec, s, Grid{t_end, output_dt});
  if (spec.engine() == Engine::InHouse) refuseUnrunnable(s.model, grid);  // before any work, as the CLI
  return checked(grid);
}

py::dict simulatePy(const Scene& s, py::object method, std::optional<std::string> integrator, std::optional<double> dt,
                    std::optional<double> tol, std::optional<double> t_end, std::optional<double> output_dt,
                    std::optional<std::string> formulation) {
  CallMethods call;
  return trajectoryDict(
      runTrajectory(s.model, runSpec(s, call.of(method, "method"), integrator, dt, tol, t_end, output_dt, formulation)));
}

py::object comparePy(const Scene& s, py::list methods, std::optional<std::string> integrator, std::optional<double> dt,
                     std::optional<double> tol, std::optional<double> t_end, std::optional<double> output_dt,
                     py::dict plugins, py::dict runs, std::optional<std::string> formulation) {
  CallMethods call;
  CompareOptions o;
  o.keywords = true;
  o.methods.clear();
  for (const py::handle& h : methods) o.methods.push_back(call.of(h, "methods"));
  for (const auto& [name, path] : namedPaths(plugins, "plugins")) {
    const Method p = call.add(addPlugin(name, path));
    probePlugin(p, s.model);
    o.methods.push_back(p);
  }
  for (const auto& [name, path] : namedPaths(runs, "runs")) o.methods.push_back(call.add(addRecordedRun(name, path, s.model)));
  if (o.methods.empty()) throw std::invalid_argument("methods: none, and no plugins or runs: nothing to compare");
  inHouseSettings(o.inhouse, Engine::InHouse, integrator, dt, tol);
  refuseUnreadInHouseSettings(o, {integrator.has_value(), dt.has_value(), tol.has_value()});
  o.useMechanismReference(s.model);
  applyFormulation(s, formulation, o.inhouse.options.loops);
  o.leaveOutUnrunnable(s.model, true);  // methods= names them: refused, as the CLI refuses named ones
  o.grid = Grid{t_end, output_dt};
  return fromJson(makeReport(runComparison(s, o)));
}

// ---- sweep and plot: the CLI's own commands ---------------------------------

// The eigenmass binary beside this module: PREFIX/bin of an installed tree
// (the module in PREFIX/lib/python3/dist-packages), else the build's bin/.
std::string cliBinary() {
  namespace fs = std::filesystem;
  const fs::path here = fs::path(py::module_::import("eigenmass").attr("__file__").cast<std::string>()).parent_path();
  for (const fs::path& p : {here.parent_path().parent_path().parent_path() / "bin" / "eigenmass", here.parent_path() / "bin" / "eigenmass"})
    if (fs::exists(p)) return p.string();
  throw std::runtime_error("the eigenmass command is not beside this module (" + here.string() + ")");
}

// Run `eigenmass ARGS`; its standard output, or a RuntimeError with its one-line error.
std::string runCli(const std::vector<std::string>& args) {
  py::module_ sp = py::module_::import("subprocess");
  std::vector<std::string> argv = {cliBinary()};
  argv.insert(argv.end(), args.begin(), args.end());
  py::object r = sp.attr("run")(argv, py::arg("capture_output") = true, py::arg("text") = true);
  const int status = r.attr("returncode").cast<int>();
  if (status == 2) {
    std::string err = r.attr("stderr").cast<std::string>();
    const std::string prefix = "eigenmass: error: ";
    if (err.rfind(prefix, 0) == 0) err.erase(0, prefix.size());
    while (!err.empty() && err.back() == '\n') err.pop_back();
    // The line names the CLI's option: name the keyword argument instead ("--results: ..." -> "results: ...").
    for (const char* option : {"--out", "--format", "--results", "--jobs"})
      if (err.rfind(std::string(option) + ":", 0) == 0) err.erase(0, 2);
    throw std::runtime_error(err);
  }
  if (status != 0 && status != 1) throw std::runtime_error("eigenmass " + args[0] + " ended with status " + std::to_string(status));
  return r.attr("stdout").cast<std::string>();
}

std::string plotPy(const py::object& input, const py::object& out, const std::string& format) {
  std::vector<std::string> a = {"plot", pathArg(input, "input"), "--format", format};
  if (!out.is_none()) a.insert(a.end(), {"--out", pathArg(out, "out")});
  return runCli(a);
}

std::string sweepPy(const py::object& plan, const py::object& results, std::optional<int> jobs) {
  std::vector<std::string> a = {"sweep", pathArg(plan, "plan")};
  if (!results.is_none()) a.insert(a.end(), {"--results", pathArg(results, "results")});
  if (jobs) a.insert(a.end(), {"--jobs", std::to_string(*jobs)});
  return runCli(a);
}

}  // namespace

PYBIND11_MODULE(eigenmass, mod) {
  mod.doc() = "eigenmass: cross-validation harness for rigid multibody dynamics (docs/python.md)";
  useEngines();
  py::class_<Scene>(mod, "Scene", "A scene or URDF robot, loaded and checked (eigenmass.load)")
      .def_property_readonly("name", [](const Scene& s) { return s.model.name; })
      .def_property_readonly("nq", [](const Scene& s) { return s.model.nq; })
      .def_property_readonly("nu", [](const Scene& s) { return s.model.nu; })
      .def_property_readonly("bodies", [](const Scene& s) { return s.model.n(); })
      .def_property_readonly("q_names", [](const Scene& s) { return s.model.qNames(); })
      .def_property_readonly("u_names", [](const Scene& s) { return s.model.uNames(); })
      .def_property_readonly("q0", [](const Scene& s) { return vec(fileOrder(s.model.q0(), s.model.qFilePermutation())); })
      .def_property_readonly("u0", [](const Scene& s) { return vec(fileOrder(s.model.u0(), s.model.uFilePermutation())); })
      .def_property_readonly("file", [](const Scene& s) { return s.source.file; })
      .def_property_readonly("sha256", [](const Scene& s) { return s.source.sha256; })
      .def_property_readonly("assembly",  // load(..., assemble=True): how far the start was moved onto the loops (None otherwise)
                             [](const Scene& s) -> py::object {
                               if (!s.source.assembly) return py::none();
                               return fromJson(sceneSourceJson(s.source).at("assembly"));  // the sidecar's own object
                             })
      .def("__repr__", [](const Scene& s) {
        return "<eigenmass.Scene " + s.model.name + ": " + std::to_string(s.model.n()) + " bodies, nu " + std::to_string(s.model.nu) + ">";
      });
  mod.def("load", &load, "Load a scene (.json) or URDF robot, with the CLI's import options", py::arg("path"),
          py::arg("balance_inertia") = false, py::arg("lock_joints") = std::vector<std::string>{}, py::arg("floating_base") = false,
          py::arg("assemble") = false);
  mod.def("equations", &equations,
          "A, B, u', eigenvalues of A and the energies at (q, u) (default: the initial state), the scene's order, from `engine`",
          py::arg("scene"), py::arg("engine") = "inhouse", py::arg("q") = py::none(), py::arg("u") = py::none());
  mod.def("simulate", &simulatePy,
          "One run: arrays t, q, u, energy, kinetic, dissipated, and its status and failure; method a name or (name, f)",
          py::arg("scene"), py::arg("method") = "classical", py::arg("integrator") = py::none(), py::arg("dt") = py::none(),
          py::arg("tol") = py::none(), py::arg("t_end") = py::none(), py::arg("output_dt") = py::none(),
          py::arg("formulation") = py::none());
  mod.def("compare", &comparePy,
          "Methods against the reference: the report `eigenmass compare --out` writes, as a dict. A method is a name "
          "or (name, f) with f(t, q, u) -> u' (numpy arrays, the scene's order), run under the in-house integrators",
          py::arg("scene"), py::arg("methods") = py::list(py::cast(std::vector<std::string>{"classical"})),
          py::arg("integrator") = py::none(), py::arg("dt") = py::none(), py::arg("tol") = py::none(),
          py::arg("t_end") = py::none(), py::arg("output_dt") = py::none(),
          py::arg("plugins") = py::dict(), py::arg("runs") = py::dict(), py::arg("formulation") = py::none());
  mod.def("plot", &plotPy, "Draw a report, precision file, trajectory, sweep results folder or extreme summary: "
          "`eigenmass plot` itself (its printed lines returned)", py::arg("input"), py::arg("out") = py::none(),
          py::arg("format") = "png");
  mod.def("sweep", &sweepPy, "Run a plan's cases and merge them: `eigenmass sweep` itself (its tables returned)",
          py::arg("plan"), py::arg("results") = py::none(), py::arg("jobs") = py::none());
  mod.def("methods", &methodNames, "Every method's name");
  mod.def("integrators", []() { return integratorNames(); }, "Every integrator's name");
  mod.def("engines", []() {
    std::vector<std::string> e;
    for (Engine x : enginesWithEquations()) e.emplace_back(engineName(x));
    return e;
  }, "The engines that give equations at a state");
}
