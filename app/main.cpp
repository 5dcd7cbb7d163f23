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

namespace {

// What a command printed must have reached standard output (a full disk, a
// closed file): otherwise it says so in one line and fails with 2, as an
// output file that cannot be written does.
int finish(int code) {
  std::cout.flush();
  const bool lost = !std::cout.good() || std::fflush(stdout) != 0 || std::ferror(stdout);
  if (!lost) return code;
  std::fputs("eigenmass: error: standard output: write failed (full or closed)\n", stderr);
  return code == 0 ? 2 : code;
}

}  // namespace

int main(int argc, char** argv) {
  em::setCommandLine(argc, argv);
  em::installInterruptCleanup();
  CLI::App app{"eigenmass: cross-validation harness for rigid multibody dynamics", "eigenmass"};
  app.set_version_flag("--version", em::versionText());
  app.require_subcommand(1);
  em::cli::addEquations(app);
  em::cli::addSimulate(app);
  em::cli::addCompare(app);
  em::cli::addPrecision(app);
  em::cli::addImport(app);
  em::cli::addCrossCheck(app);
  em::cli::addExtreme(app);
  em::cli::addSweep(app);
  em::cli::addPlot(app);
  if (argc < 2) {
    std::fputs(app.help().c_str(), stderr);
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return finish(app.exit(e));  // --help, --version
    std::fprintf(stderr, "eigenmass: error: %s (see --help)\n", e.what());
    return 2;
  }
  return finish(em::cli::exitCode());
}
