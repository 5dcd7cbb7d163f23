// Timing of one right-hand-side evaluation per method against every engine's
// forward dynamics that its row names (EngineCode::forward_call: Simbody's
// realize(Acceleration), MuJoCo's mj_forward), for chains of n links,
// measured in the same run; and the machine's matrix-multiply rate, against
// which the eigen method's N^3 part is judged. Each time is the median (with
// min and max) over batches; compare them only as ratios within one run.
// Output: the table of docs/performance.md, and with --out a JSON file.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "compare/provenance.hpp"
#include "compare/report.hpp"
#include "io/atomic_file.hpp"
#include "io/scene.hpp"
#include "io/shipped.hpp"
#include "solver/dynamics.hpp"
#include "solver/eigenfactor_ops.hpp"
#include "compare/crosscheck.hpp"
#include "reference/engine.hpp"
#include "outside/plugin.hpp"

using namespace em;

namespace {

std::vector<Method> g_plugins;  // --plugin: methods from outside, timed beside the engines' u'

// Seconds per call over `batches` batches of about 50 ms each.
struct Timing {
  double median = 0, min = 0, max = 0;
};

Timing secondsPerCall(const std::function<void()>& f, int batches = 7) {
  using clock = std::chrono::steady_clock;
  f();
  long reps = 1;
  for (;;) {  // calibrate the batch size
    const auto t0 = clock::now();
    for (long i = 0; i < reps; ++i) f();
    if (std::chrono::duration<double>(clock::now() - t0).count() > 0.05) break;
    reps *= 2;
  }
  std::vector<double> t(batches);
  for (double& tb : t) {
    const auto t0 = clock::now();
    for (long i = 0; i < reps; ++i) f();
    tb = std::chrono::duration<double>(clock::now() - t0).count() / reps;
  }
  std::sort(t.begin(), t.end());
  return {t[batches / 2], t.front(), t.back()};
}

// The chain of n links as the data files define it (tools/make_scenes.py):
// data/scenes/chainNN.json, or data/bench/ for the sizes only benchmarks use.
Model chain(int n) {
  char name[32];
  std::snprintf(name, sizeof name, "chain%02d.json", n);
  for (const char* dir : {"data/scenes/", "data/bench/"}) {
    const std::string path = shippedFile(std::string(dir) + name, EM_SOURCE_DIR);
    if (std::FILE* f = std::fopen(path.c_str(), "r")) {
      std::fclose(f);
      return loadScene(path).model;
    }
  }
  throw std::runtime_error(std::string(name) + ": no such chain in data/scenes or data/bench (tools/make_scenes.py)");
}

// One engine's forward dynamics, timed, and its A and B against the in-house
// ones at the initial state (max |diff| / max |in-house|).
struct EngineTiming {
  std::string name;  ///< its row's id: the JSON key
  Timing t;
  double A_err = 0, B_err = 0;
};

// One chain's timings (seconds per call) and the engines' agreement check.
struct Row {
  int n = 0, N = 0;
  Timing classical, articulated, eigen, eigen_refined, eigen_n3, jacobi, gemm;  // eigen_refined: eigen with refine 2
  std::vector<EngineTiming> engines;  ///< in engineRows() order, those with a forward_call
  double articulated_err = 0;  ///< articulated's u' vs classical's, max |diff| / max |classical|
  double cond_A = 0;           ///< cond(A) at the initial state
  /// Every engine's u' as a method under the in-house integrators (dart-udot),
  /// one right-hand-side evaluation each, and its u' against classical's.
  std::vector<std::pair<std::string, Timing>> engine_udot;
  std::vector<double> engine_udot_err;
};

Row measure(int n);

// Whether --out can be written: a device or FIFO as it is (io/atomic_file.hpp),
// else a probe file beside it can be created.
bool writableOutput(const std::string& out) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(out, ec)) return false;
  if (fs::exists(out, ec) && !fs::is_regular_file(out, ec)) return true;
  const std::string probe = out + ".probe." + std::to_string(::getpid());
  if (!std::ofstream(probe)) return false;
  std::remove(probe.c_str());
  return true;
}
void printTable(const std::vector<Row>& rows);
nlohmann::json toJson(const std::vector<Row>& rows, int threads);

}  // namespace

namespace {

struct BenchArgs {
  std::vector<int> sizes = {5, 10, 20, 50, 100};
  std::string out;
  std::vector<std::string> plugins;
  int threads = 1;
};

void addBenchOptions(CLI::App& app, BenchArgs& a) {
  app.add_option("sizes", a.sizes, "Chain lengths n (data/scenes/chainNN.json or data/bench/)")
      ->check(CLI::Range(1, 999))
      ->capture_default_str();
  app.add_option("--out", a.out, "Also write the timings as JSON (machine, median/min/max per method and n)");
  app.add_option("--plugin", a.plugins,
                 "A method from outside, NAME=path/libx.so (docs/plugins.md), timed beside the engines' u' in this "
                 "process (probed first in a child process at each chain's initial state; repeatable)");
  app.add_option("--threads", a.threads, "Threads of Eigen's matrix products (a build with -DEM_OPENMP=ON)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
}

// Settings that cannot be honoured, refused before any timing: "" when all can.
std::string refusedSetting(const BenchArgs& a) {
#ifdef _OPENMP
  Eigen::setNbThreads(a.threads);
#else
  if (a.threads != 1) return "--threads: this build has no OpenMP (configure with -DEM_OPENMP=ON)";
#endif
  if (!a.out.empty() && !writableOutput(a.out)) return "--out " + a.out + ": cannot write here";  // now, not after the benchmark
  return "";
}

void loadPlugins(const BenchArgs& a) {
  for (const std::string& v : a.plugins) {
    const auto [name, path] = splitNamedFile("--plugin", v);
    try {
      g_plugins.push_back(addPlugin(name, path));
      for (int n : a.sizes) probePlugin(g_plugins.back(), chain(n));
    } catch (const std::exception& e) {
      throw std::invalid_argument(std::string("--plugin: ") + e.what());
    }
  }
}

// Timings compare the same equations: an engine's A and B within round-off of
// ours (chains have no full inertias), every u' within ~eps cond(A) of
// classical's (a plugin's own accuracy is its business: printed, not held).
// The first disagreement, or "".
std::string disagreement(const Row& r, int n) {
  char line[256];
  for (const EngineTiming& e : r.engines)
    if (std::max(e.A_err, e.B_err) > 1e-12) {
      std::snprintf(line, sizeof line, "%s's A or B differs from the in-house one on chain %d (A %.3g, B %.3g)", e.name.c_str(), n,
                    e.A_err, e.B_err);
      return line;
    }
  for (size_t k = 0; k + g_plugins.size() < r.engine_udot.size(); ++k)
    if (r.engine_udot_err[k] > 1e-12 * r.cond_A) {
      std::snprintf(line, sizeof line, "%s's u' differs from classical's on chain %d (%.3g, cond(A) %.3g)",
                    r.engine_udot[k].first.c_str(), n, r.engine_udot_err[k], r.cond_A);
      return line;
    }
  if (r.articulated_err > 1e-12 * r.cond_A) {
    std::snprintf(line, sizeof line, "articulated's u' differs from classical's on chain %d (%.3g, cond(A) %.3g)", n,
                  r.articulated_err, r.cond_A);
    return line;
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  setCommandLine(argc, argv);
  useEngines();
  BenchArgs a;
  CLI::App app{"Times one right-hand-side evaluation per method against the engines' forward dynamics (Simbody's realize(Acceleration), MuJoCo's mj_forward)",
               "eigenmass_bench"};
  addBenchOptions(app, a);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "eigenmass_bench: error: %s (see --help)\n", e.what());
    return 2;
  }
  if (const std::string why = refusedSetting(a); !why.empty()) {
    std::fprintf(stderr, "eigenmass_bench: error: %s\n", why.c_str());
    return 2;
  }
  try {
    loadPlugins(a);
    std::vector<Row> rows;
    for (int n : a.sizes) {
      rows.push_back(measure(n));
      if (const std::string why = disagreement(rows.back(), n); !why.empty()) {
        std::fprintf(stderr, "eigenmass_bench: %s\n", why.c_str());
        return 1;
      }
    }
    printTable(rows);
    if (!a.out.empty()) writeJsonAtomic(toJson(rows, a.threads), a.out);
    return finishStandardOutput("eigenmass_bench", 0);  // a table lost to a full disk is an error
  } catch (const std::exception& e) {
    std::fprintf(stderr, "eigenmass_bench: error: %s\n", e.what());
    return 2;
  }
}

namespace {

// Every engine whose row names its forward dynamics: timed at the initial state.
std::vector<EngineTiming> measureEngines(const Model& m, const Workspace& ws) {
  std::vector<EngineTiming> out;
  const Eigen::VectorXd q = m.q0(), u = m.u0();
  for (const EngineRow& row : engineRows()) {
    if (!row.code.forward_call || !row.code.model) continue;
    std::unique_ptr<EngineModel> engine = row.code.model(m);
    const EngineEquations eq = engine->at(q, u);
    out.push_back({row.info.name, secondsPerCall([&] { engine->forward(q, u); }), relativeDifference(eq.A, ws.A),
                   relativeDifference(eq.B, ws.B)});
  }
  return out;
}

const char* forwardCall(const std::string& engine) {
  for (const EngineRow& row : engineRows())
    if (row.info.name == engine) return row.code.forward_call;
  return "";
}

// The eigen method's N^3 part alone (eigenRates: A'C^T, G = C A'C^T, C' = -Omega C).
Timing eigenN3(const Model& m, Dynamics& eigen, const Eigen::VectorXd& y) {
  const int N = m.nu;
  Workspace ws(m);
  formEquations(m, y.data(), y.data() + m.nq, ws, true);
  // ExtraState::CLambda: C (N*N), then lambda (N).
  Eigen::Map<const RowMatrix> C(y.data() + eigen.offsetExtra(), N, N);
  Eigen::Map<const Eigen::VectorXd> lambda(y.data() + eigen.offsetExtra() + N * N, N);
  Eigen::MatrixXd Omega(N, N), AdotCt(N, N);
  Eigen::VectorXd lambda_dot(N);
  RowMatrix Cdot(N, N);
  return secondsPerCall([&] { eigenRates(C, lambda, ws.Adot, 0.0, Omega, AdotCt, lambda_dot, Cdot); });
}

Row measure(int n) {
  const Model m = chain(n);
  Row r;
  r.n = n;
  r.N = m.nu;
  Dynamics classical(m, Method::Classical), eigen(m, Method::Eigen), jacobi(m, Method::EigenJacobi);
  Eigen::VectorXd yc = classical.initialState(m.q0(), m.u0()), dc(yc.size());
  Eigen::VectorXd ye = eigen.initialState(m.q0(), m.u0()), de(ye.size());
  Eigen::VectorXd yj = ye;
  r.classical = secondsPerCall([&] { classical.rhs(0, yc.data(), dc.data()); });
  Dynamics articulated(m, Method::Articulated);
  Eigen::VectorXd da(yc.size());
  r.articulated = secondsPerCall([&] { articulated.rhs(0, yc.data(), da.data()); });
  r.articulated_err = relativeDifference(da, dc);
  r.cond_A = conditionNumber(classical.workspace().A);
  r.eigen = secondsPerCall([&] { eigen.rhs(0, ye.data(), de.data()); });
  MethodOptions refine2;
  refine2.params["refine"] = 2;  // two residual corrections (docs/theory.md §8): 6 N^2 multiply-adds
  Dynamics refined(m, Method::Eigen, refine2);
  r.eigen_refined = secondsPerCall([&] { refined.rhs(0, ye.data(), de.data()); });
  r.eigen_n3 = eigenN3(m, eigen, ye);
  // The correction after a step: forming A and the Jacobi sweeps from an exact basis.
  StepInfo step;
  r.jacobi = secondsPerCall([&] { yj = ye; jacobi.afterStep(0, yj.data(), step); });
  classical.rhs(0, yc.data(), dc.data());
  r.engines = measureEngines(m, classical.workspace());
  std::vector<Method> others;  // engines' u' under the in-house integrators, then the plugins'
  for (const EngineRow& row : engineRows())
    if (row.code.udot_method.name) others.push_back(parseMethod(row.code.udot_method.name));
  others.insert(others.end(), g_plugins.begin(), g_plugins.end());
  for (Method method : others) {
    Dynamics other(m, method);
    Eigen::VectorXd y = other.initialState(m.q0(), m.u0()), d(y.size());
    r.engine_udot.emplace_back(methodName(method), secondsPerCall([&] { other.rhs(0, y.data(), d.data()); }));
    r.engine_udot_err.push_back(relativeDifference(d.segment(m.nq, m.nu), dc.segment(m.nq, m.nu)));
  }
  const Eigen::MatrixXd X = Eigen::MatrixXd::Random(r.N, r.N), Y = Eigen::MatrixXd::Random(r.N, r.N);
  Eigen::MatrixXd Z(r.N, r.N);
  r.gemm = secondsPerCall([&] { Z.noalias() = X * Y; });
  return r;
}

// Flops of the eigen N^3 part as written (docs/performance.md): A'C^T 2N^3,
// the upper half of G N^3, Omega C 2N^3.
double eigenN3Flops(int N) { return 5.0 * N * N * N; }
double gemmFlops(int N) { return 2.0 * N * N * N; }

void printTable(const std::vector<Row>& rows) {
  std::printf("Median of 7 batches, microseconds per call.");
  if (!rows.empty())
    for (const EngineTiming& e : rows.front().engines) std::printf(" %s = %s;", e.name.c_str(), forwardCall(e.name));
  std::printf("\nN3 / GEMM = the eigen N^3 part's flop rate over the machine's N x N matrix multiply.\n\n");
  std::printf("| n | N | classical | articulated | articulated / classical | eigen | eigen refine 2 | eigen N^3 part | jacobi step |");
  if (!rows.empty())
    for (const EngineTiming& e : rows.front().engines) std::printf(" %s | classical / %s |", e.name.c_str(), e.name.c_str());
  std::printf(" refine 2 / eigen | jacobi / eigen | N3 / GEMM | GEMM GFLOP/s |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
  if (!rows.empty())
    for (size_t k = 0; k < rows.front().engines.size(); ++k) std::printf("---:|---:|");
  std::printf("---:|---:|---:|---:|\n");
  for (const Row& r : rows) {
    const double us = 1e6;
    const double rate_n3 = eigenN3Flops(r.N) / r.eigen_n3.median, rate_gemm = gemmFlops(r.N) / r.gemm.median;
    std::printf("| %d | %d | %.2f | %.2f | %.3f | %.2f | %.2f | %.2f | %.2f |", r.n, r.N, us * r.classical.median,
                us * r.articulated.median, r.articulated.median / r.classical.median, us * r.eigen.median,
                us * r.eigen_refined.median, us * r.eigen_n3.median, us * r.jacobi.median);
    for (const EngineTiming& e : r.engines) std::printf(" %.2f | %.2f |", us * e.t.median, r.classical.median / e.t.median);
    std::printf(" %.2f | %.2f | %.2f | %.1f |\n", r.eigen_refined.median / r.eigen.median, r.jacobi.median / r.eigen.median,
                rate_n3 / rate_gemm, 1e-9 * rate_gemm);
  }
  if (!rows.empty() && !rows.front().engine_udot.empty()) {
    std::printf("\nEngines' (and plugins') u' under the in-house integrators, microseconds per evaluation (their u' against classical's):\n\n| n |");
    for (const auto& [name, t] : rows.front().engine_udot) std::printf(" %s | / classical | u' diff |", name.c_str());
    std::printf("\n|---:|");
    for (size_t k = 0; k < rows.front().engine_udot.size(); ++k) std::printf("---:|---:|---:|");
    std::printf("\n");
    for (const Row& r : rows) {
      std::printf("| %d |", r.n);
      for (size_t k = 0; k < r.engine_udot.size(); ++k)
        std::printf(" %.2f | %.2f | %.1e |", 1e6 * r.engine_udot[k].second.median, r.engine_udot[k].second.median / r.classical.median,
                    r.engine_udot_err[k]);
      std::printf("\n");
    }
  }
  for (const Row& r : rows)
    for (const EngineTiming& e : r.engines)
      std::printf("%schain %d: %s vs in-house at the initial state, A %.1e, B %.1e (max |diff| / max |in-house|)",
                  &r == &rows.front() && &e == &r.engines.front() ? "\n" : "; ", r.n, e.name.c_str(), e.A_err, e.B_err);
  std::printf("\n");
}

nlohmann::json timingJson(const char* name, int n, const Timing& t, int threads) {
  nlohmann::json j = {{"name", name}, {"n", n}, {"median_us", 1e6 * t.median}, {"min_us", 1e6 * t.min}, {"max_us", 1e6 * t.max}};
  if (threads != 1) j["threads"] = threads;  // Eigen's products only; the engines stay serial
  return j;
}

nlohmann::json toJson(const std::vector<Row>& rows, int threads) {
  nlohmann::json results = nlohmann::json::array();
  for (const Row& r : rows) {
    for (auto [name, t] : {std::pair<const char*, const Timing*>{"classical", &r.classical},
                           {"articulated", &r.articulated}, {"eigen", &r.eigen},
                           {"eigen-refine2", &r.eigen_refined},
                           {"eigen-n3", &r.eigen_n3}, {"jacobi-step", &r.jacobi}, {"gemm", &r.gemm}})
      results.push_back(timingJson(name, r.n, *t, threads));
    for (const EngineTiming& e : r.engines) results.push_back(timingJson(e.name.c_str(), r.n, e.t, 1));
    for (const auto& [name, t] : r.engine_udot) results.push_back(timingJson(name.c_str(), r.n, t, 1));
  }
  return {{"machine", provenance()}, {"results", results}};
}

}  // namespace
