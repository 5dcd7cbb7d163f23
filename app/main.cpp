// The `eigenmass` command-line tool: equations, simulate, compare, precision, import, crosscheck,
// extreme, sweep, plot.
// One exit-code scheme: 0 ok, 1 a run failed or the gate broke, 2 bad input
// or options (CLI11's own parse errors included), 130/143 interrupted.
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "app/cli.hpp"
#include "compare/provenance.hpp"
#include "io/atomic_file.hpp"
#include "io/shipped.hpp"
#include "reference/engine.hpp"

int main(int argc, char** argv) {
  em::setCommandLine(argc, argv);
  em::installInterruptCleanup();
  em::useEngines();  // every engine's row in the registry before the options are built from it
  CLI::App app{"eigenmass: cross-validation harness for rigid multibody dynamics", "eigenmass"};
  // Where tools/plot.py and data/ are read from: an installed tree's own share/eigenmass, else the source tree.
  std::string shipped = em::shippedFile(".", EM_SOURCE_DIR);
  shipped.erase(shipped.size() - 2);  // the "/."
  app.set_version_flag("--version", em::versionText() + "\nshipped files: " + shipped);
  app.require_subcommand(1);
  em::cli::addEquations(app);
  em::cli::addSimulate(app);
  em::cli::addCompare(app);
  em::cli::addPrecision(app);
  em::cli::addImport(app);
  em::cli::addCrossCheck(app);
  em::cli::addExtreme(app);
  em::cli::addSweep(app);
  em::cli::addEngineStudy(app);
  em::cli::addBenchmark(app);
  em::cli::addPlot(app);
  em::cli::refuseEmptyPaths(app);
  if (argc < 2) {
    std::fputs(app.help().c_str(), stderr);
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return em::finishStandardOutput("eigenmass", app.exit(e));  // --help, --version
    std::fprintf(stderr, "eigenmass: error: %s (see --help)\n", em::cli::oneLine(e.what()).c_str());
    return 2;
  }
  // What a command printed must have reached standard output, as an output
  // file that cannot be written fails with 2.
  return em::finishStandardOutput("eigenmass", em::cli::exitCode());
}
