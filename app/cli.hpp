#pragma once
/// The `eigenmass` CLI: one file per subcommand (cmd_*.cpp) and what they
/// share. Names offered on the command line come from the registry, so
/// `--help` lists exactly what runs.
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "compare/engines.hpp"
#include "solver/trajectory.hpp"

namespace em {
struct Plan;
}

namespace em::cli {

void addEquations(CLI::App& app);
void addSimulate(CLI::App& app);
void addCompare(CLI::App& app);
void addPrecision(CLI::App& app);
void addImport(CLI::App& app);
void addCrossCheck(CLI::App& app);
void addExtreme(CLI::App& app);
void addSweep(CLI::App& app);
void addPlot(CLI::App& app);
void addEngineStudy(CLI::App& app);
void addBenchmark(CLI::App& app);
/// Run every case of `plan` (read from `plan_path`) not done yet in `dir` on
/// `jobs` workers (0: every core) and merge them, or, with `list`, print one
/// command per case (sweep and engine-study share it). Returns the exit status.
int sweepPlan(const Plan& plan, const std::string& plan_path, const std::string& dir, int jobs, bool list);
/// Refuse what a sweep writes into `dir` (each case's result and CSV, the merged files) where it is one of
/// its inputs (the plan, its scenes): a plan or scene kept in the results folder under a case's name.
/// --progress and --no-progress (compare/progress.hpp), excluding each other.
void addProgressFlags(CLI::App* cmd);
void refuseSweepOverInputs(const Plan& plan, const std::string& plan_path, const std::string& dir);
/// Refuse a path with a line break where --list prints it (each case's command must stay one line).
void refuseLineBreaks(const std::vector<std::pair<const char*, std::string>>& paths);
/// Exit status of the subcommand that ran (0 ok, 1 gate broken / run failed, 2 bad input).
int exitCode();

/// Run a subcommand body: an exception ends in one line on stderr and exit
/// status 2, never a crash; otherwise the body's status is the exit status.
void guarded(const std::function<int()>& body);
/// `text` on one line: line breaks and other control characters escaped (\n, \x1b), UTF-8 kept.
std::string oneLine(const std::string& text);

/// Make ready to write `path` before any computation: its folder exists and
/// takes a file, and neither it nor a file written beside it under a derived
/// name (`derived`: "x.csv.json" beside "x.csv") is one of `inputs` (never
/// overwrite an input). Throws one line naming `option` and the path otherwise.
void prepareOutput(const std::string& option, const std::string& path, const std::vector<std::string>& inputs,
                   const std::vector<std::string>& derived = {});
/// Throws one line naming `option` (given as `given`) when a file of `written` is one of `inputs`.
void refuseInputs(const std::string& option, const std::string& given, const std::vector<std::string>& written,
                  const std::vector<std::string>& inputs);
/// Outputs of one command, each (what names it: an option or an input, its
/// path): two that are one file, existing or not, are refused in one line
/// naming both, before any run (one output never overwrites another).
void refuseCollisions(const std::vector<std::pair<std::string, std::string>>& outputs);

/// The same for a folder that will receive files.
void prepareFolder(const std::string& option, const std::string& dir);

/// Progress on stderr: "running <what> ...".
void progress(const std::string& what);

/// Write a trajectory as CSV and, beside it, `<path>.json`: the run that made
/// it (RunSpec), its status and failure, and the provenance.
void writeTrajectory(const Trajectory& tr, const std::string& path, const SceneSource* source = nullptr);
/// Whether `path` (followed through links) is, or will be, a regular file:
/// no sidecar is written beside a device or a FIFO (--out /dev/stdout).
bool regularOutput(const std::string& path);

/// The scene a subcommand reads: its path and, for a URDF, the import options.
struct SceneArg {
  std::string path;
  UrdfOptions urdf;
  bool assemble = false;  ///< --assemble
  Scene load() const { return loadScene(path, urdf, assemble); }
};
/// The positional `scene`, --balance-inertia and --lock-joint.
void addSceneArg(CLI::App* cmd, SceneArg& s);

/// A step option (`dt_option`) or a tolerance option (`tol_option`) given on
/// `cmd` that `integrator` does not read is refused in one line, not ignored.
void refuseUnreadSetting(const CLI::App& cmd, Integrator integrator, const std::string& dt_option, const std::string& tol_option);

/// Options the runs would not read are refused in one line, not ignored: a
/// method option (--refine, --block-gap) that none of `methods` takes, and
/// --no-step-retry when no in-house run of the command is adaptive.
void refuseUnreadRunOptions(const CLI::App& cmd, const std::vector<Method>& methods, bool adaptive_inhouse);

/// A list option (`option`) that names a value twice is refused in one line:
/// its rows or reports would repeat or overwrite each other.
template <class T>
void refuseDuplicates(const std::string& option, const std::vector<T>& values) {
  for (size_t i = 0; i < values.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (values[i] == values[j]) {
        std::ostringstream v;
        v << values[i];
        throw std::invalid_argument(option + ": " + v.str() + " is listed twice");
      }
}

/// A finite number > 0 (every step, tolerance, time and threshold option).
CLI::Validator positiveFinite();
/// A finite number in [lo, hi] (CLI::Range lets NaN through).
CLI::Validator finiteRange(double lo, double hi);

/// One rule for an empty path (issue 42): every option that names a file or
/// a folder to write or read (--out, --csv-dir, --out-dir, --doc, --results,
/// --merge, --gate, --expect, --run, --plugin) refuses "" in one line, on every
/// subcommand of `app`; leaving the option out is how its default is asked.
void refuseEmptyPaths(CLI::App& app);

/// What every running subcommand takes: the output grid, the step budget,
/// the retry switch and the methods' own options (the registry rows' params).
struct RunArgs {
  double t_end = 0, output_dt = 0;
  bool allow_long_run = false;
  bool no_step_retry = false;
  std::map<std::string, double> params;  ///< every method option by name, at its row's fallback unless given
  LoopOptions loops;                     ///< --formulation, --baumgarte-alpha, --baumgarte-beta (a mechanism's)
  std::string formulation = "projection";
  /// The grid as asked on `cmd`: what was not given stays absent (the scene's).
  Grid asked(const CLI::App& cmd) const;
  /// --allow-long-run lifts the step budget of `spec` (MethodOptions::max_steps);
  /// --no-step-retry ends an adaptive run at a failed trial stage; each
  /// method option (--refine, --block-gap, ...) goes to MethodOptions::params.
  void applyTo(MethodOptions& options) const;
  void applyTo(RunSpec& spec) const { applyTo(spec.options); }
};
/// --t-end, --output-dt (help `output_dt_help`), --allow-long-run, --no-step-retry, one option per
/// method option of the registry (methodParams()), --progress, --no-progress.
void addRunOptions(CLI::App* cmd, RunArgs& g, const std::string& output_dt_help);
/// --formulation, --baumgarte-alpha, --baumgarte-beta and --al-penalty-ratio
/// given on a scene without loops are refused in one line, not ignored; so is
/// --al-penalty-ratio under another formulation.
void refuseUnreadLoopOptions(const CLI::App& cmd, const Model& m);
/// On a scene with loops, a formulation option the run would not read is
/// refused in one line (issue 73, item 7): --formulation, --baumgarte-alpha,
/// --baumgarte-beta and --al-penalty-ratio where no method is in-house (an
/// engine closes its loops its own way) or the in-house integrator is ida
/// (its own index-2 formulation); Baumgarte's values under the augmented
/// Lagrangian; a formulation that brings its own integrator under another.
void refuseUnreadFormulationOptions(const CLI::App& cmd, const std::vector<Method>& methods, Integrator inhouse,
                                    Formulation f, const Model& m);

/// What a user brings on the command line (docs/plugins.md): --plugin
/// NAME=path/libx.so (repeatable), --plugin-timeout, and where a command
/// compares runs, --run NAME=FILE.csv (repeatable).
struct OutsideArgs {
  std::vector<std::string> plugins, runs;  ///< "NAME=path" each
  double plugin_timeout = 0;               ///< 0: kPluginTimeout
  /// Load every one against the scene (a plugin probed at its initial state,
  /// a run read and checked): one line naming the option and the file,
  /// before any run. Returns the methods they add, in order.
  std::vector<std::string> load(const Scene& scene) const;
  /// Every file named (inputs: an output may never replace one).
  std::vector<std::string> files() const;
};
void addOutsideOptions(CLI::App* cmd, OutsideArgs& o, bool with_runs);

/// Validators fed from the registry: a method name; an integrator name (of one engine).
CLI::Validator methodValidator();
CLI::Validator integratorValidator();
CLI::Validator integratorValidator(Engine engine);

/// "Methods: classical, eigen, ...": a help text followed by the registry's names.
std::string helpWithNames(const std::string& text, const std::vector<std::string>& names);

}  // namespace em::cli
