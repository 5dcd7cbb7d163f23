#pragma once
/// Subcommands of the `eigenmass` CLI.
#include <CLI/CLI.hpp>

namespace em::cli {

void addEquations(CLI::App& app);
void addSimulate(CLI::App& app);
void addCompare(CLI::App& app);
void addPrecision(CLI::App& app);
/// Exit status of the subcommand that ran (0 ok, 1 gate broken / run failed, 2 bad input).
int exitCode();

}  // namespace em::cli
