// Timing of one right-hand-side evaluation per method against Simbody's
// realize(Acceleration), for chains of n links, measured in the same run.
// Times are the minimum over batches (robust to a shared, noisy machine);
// compare them only as ratios within one run. Output: docs/performance.md.
#include <chrono>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/scene.hpp"
#include "reference/simbody_reference.hpp"
#include "solver/dynamics.hpp"

using namespace em;

namespace {

// Seconds per call: the fastest of `batches` batches of about 50 ms each.
double secondsPerCall(const std::function<void()>& f, int batches = 7) {
  using clock = std::chrono::steady_clock;
  f();
  long reps = 1;
  for (;;) {  // calibrate the batch size
    const auto t0 = clock::now();
    for (long i = 0; i < reps; ++i) f();
    if (std::chrono::duration<double>(clock::now() - t0).count() > 0.05) break;
    reps *= 2;
  }
  double best = 1e300;
  for (int b = 0; b < batches; ++b) {
    const auto t0 = clock::now();
    for (long i = 0; i < reps; ++i) f();
    best = std::min(best, std::chrono::duration<double>(clock::now() - t0).count() / reps);
  }
  return best;
}

// The chain of n links as the data files define it (tools/make_scenes.py):
// data/scenes/chainNN.json, or data/bench/ for the sizes only benchmarks use.
Model chain(int n) {
  char name[32];
  std::snprintf(name, sizeof name, "chain%02d.json", n);
  const std::string root = EM_SOURCE_DIR;
  for (const char* dir : {"/data/scenes/", "/data/bench/"}) {
    const std::string path = root + dir + name;
    if (std::FILE* f = std::fopen(path.c_str(), "r")) {
      std::fclose(f);
      return loadScene(path).model;
    }
  }
  throw std::runtime_error(std::string(name) + ": no such chain in data/scenes or data/bench (tools/make_scenes.py)");
}

int run(const std::vector<int>& sizes);

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes = {5, 10, 20, 50, 100};
  CLI::App app{"Times one right-hand-side evaluation per method against Simbody's realize(Acceleration)",
               "eigenmass_bench"};
  app.add_option("sizes", sizes, "Chain lengths n (data/scenes/chainNN.json or data/bench/)")
      ->check(CLI::Range(1, 999))
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::fprintf(stderr, "eigenmass_bench: error: %s (see --help)\n", e.what());
    return 2;
  }
  try {
    return run(sizes);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "eigenmass_bench: error: %s\n", e.what());
    return 2;
  }
}

namespace {
int run(const std::vector<int>& sizes) {
  std::printf("| n links | N = nu | classical rhs (us) | eigen rhs (us) | jacobi step (us) | Simbody realize (us) | classical / Simbody | eigen / classical |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int n : sizes) {
    const Model m = chain(n);
    Dynamics classical(m, Method::Classical), eigen(m, Method::Eigen), jacobi(m, Method::EigenJacobi);
    Eigen::VectorXd yc = classical.initialState(m.q0(), m.u0()), dc(yc.size());
    Eigen::VectorXd ye = eigen.initialState(m.q0(), m.u0()), de(ye.size());
    Eigen::VectorXd yj = ye;
    const double t_classical = secondsPerCall([&] { classical.rhs(0, yc.data(), dc.data()); });
    const double t_eigen = secondsPerCall([&] { eigen.rhs(0, ye.data(), de.data()); });
    // The correction after a step: forming A and the Jacobi sweeps from an exact basis.
    StepInfo step;
    const double t_jacobi = secondsPerCall([&] { yj = ye; jacobi.afterStep(0, yj.data(), step); });
    SimbodyReference ref(m);
    const Eigen::VectorXd q = m.q0(), u = m.u0();
    // setState invalidates the Position stage, so each call realizes from scratch.
    const double t_simbody = secondsPerCall([&] { ref.setState(q, u); ref.udot(); });
    std::printf("| %d | %d | %.2f | %.2f | %.2f | %.2f | %.1f | %.2f |\n", n, m.nu, 1e6 * t_classical, 1e6 * t_eigen,
                1e6 * t_jacobi, 1e6 * t_simbody, t_classical / t_simbody, t_eigen / t_classical);
    std::fflush(stdout);
  }
  return 0;
}
}  // namespace
