#pragma once
/// The `eigenmass` CLI: one file per subcommand (cmd_*.cpp) and what they
/// share. Names offered on the command line come from the registry, so
/// `--help` lists exactly what runs.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "solver/registry.hpp"

namespace em::cli {

void addEquations(CLI::App& app);
void addSimulate(CLI::App& app);
void addCompare(CLI::App& app);
void addPrecision(CLI::App& app);
/// Exit status of the subcommand that ran (0 ok, 1 gate broken / run failed, 2 bad input).
int exitCode();

/// Run a subcommand body: an exception ends in one line on stderr and exit
/// status 2, never a crash; otherwise the body's status is the exit status.
void guarded(const std::function<int()>& body);

/// Create the folder a file is to be written into.
void ensureParentDir(const std::string& path);

/// Progress on stderr: "running <what> ...".
void progress(const std::string& what);

/// Validators fed from the registry: a method name; an integrator name (of one engine).
CLI::Validator methodValidator();
CLI::Validator integratorValidator();
CLI::Validator integratorValidator(Engine engine);

/// "Methods: classical, eigen, ...": a help text followed by the registry's names.
std::string helpWithNames(const std::string& text, const std::vector<std::string>& names);

}  // namespace em::cli
