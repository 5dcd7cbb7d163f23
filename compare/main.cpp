// The `eigenmass` command-line tool: equations, simulate, compare, precision.
#include <CLI/CLI.hpp>
#include "compare/cli.hpp"

int main(int argc, char** argv) {
  CLI::App app{"eigenmass: cross-validation harness for rigid multibody dynamics"};
  app.require_subcommand(1);
  em::cli::addEquations(app);
  em::cli::addSimulate(app);
  em::cli::addCompare(app);
  em::cli::addPrecision(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return em::cli::exitCode();
}
