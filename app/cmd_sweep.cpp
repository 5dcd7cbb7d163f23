// `eigenmass sweep PLAN`: run a plan's cases on local worker processes (or
// one case, or list one command per case for GNU parallel or Slurm), then
// merge every case's result into one CSV and the tables (docs/sweep.md).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>

#include "app/cli.hpp"
#include "io/json_input.hpp"
#include "sweep/sweep.hpp"

namespace em::cli {

namespace {

namespace fs = std::filesystem;

struct SweepArgs {
  std::string plan, results, merge, one_case;
  int jobs = 0;
  bool list = false;
};

int mergeInto(const Plan& plan, const std::string& dir) {
  std::vector<std::string> missing;
  const std::vector<CaseRecord> records = collectRecords(plan, dir, missing);
  if (records.empty()) {  // an empty or foreign folder: no empty tables, no "merged"
    std::fprintf(stderr, "sweep: no case result of plan '%s' in %s: nothing merged\n", plan.name.c_str(), dir.c_str());
    return 2;
  }
  // An engine study's margins: its contenders timed in interleaved rounds (read
  // back from <dir>/margins.json when it holds these runs), once every case is in.
  std::optional<Interleaved> timed;
  if (plan.hasTable(PlanTable::EngineStudy) && missing.empty()) {
    std::vector<std::string> scenes;
    for (const PlanScene& ps : plan.scenes) scenes.push_back(ps.stem());
    const std::vector<std::string> contenders = engineStudyContenders(records, scenes, plan.t_end);
    std::fprintf(stderr, "sweep: %zu runs timed over %d interleaved rounds for the margins\n", contenders.size(), kInterleavedRounds);
    timed = timeInterleaved(plan, contenders, dir, kInterleavedRounds);
  }
  std::fputs(writeMerged(plan, dir, records, missing, timed ? &*timed : nullptr).c_str(), stdout);
  std::printf("merged: %s, %s\n", (fs::path(dir) / (plan.name + ".csv")).string().c_str(),
              (fs::path(dir) / (plan.name + ".md")).string().c_str());
  if (missing.empty()) return 0;
  std::fprintf(stderr, "sweep: %zu of %zu cases have no result in %s (first: %s)\n", missing.size(),
               missing.size() + records.size(), dir.c_str(), missing[0].c_str());
  return 1;
}

}  // namespace

void refuseSweepOverInputs(const Plan& plan, const std::string& plan_path, const std::string& dir) {
  std::vector<std::string> inputs = {plan_path}, written;
  for (const PlanScene& s : plan.scenes) inputs.push_back(s.file);
  for (const char* tail : {".csv", ".md", "-ensemble.csv", "-prediction.csv"})
    written.push_back((fs::path(dir) / (plan.name + tail)).string());
  std::vector<std::string> merged = written, cases;  // the merge reads every case file: none may be a merged output
  for (const SweepCase& c : planCases(plan)) {
    written.push_back(caseFile(dir, c));
    written.push_back(caseCsv(dir, c));
    cases.push_back(caseFile(dir, c));
  }
  refuseInputs("--results", dir, written, inputs);
  refuseInputs("--results", dir, merged, cases);
}

namespace {

int runOneCase(const Plan& plan, const std::string& name, const std::string& dir) {
  for (const SweepCase& c : planCases(plan))
    if (c.name == name) {
      std::printf("%s: %s\n", c.name.c_str(), runCase(plan, c, dir) ? "done" : "already has a result");
      return 0;
    }
  throw std::invalid_argument("--case " + name + ": not a case of " + plan.file + " (--list names them)");
}

}  // namespace

void refuseLineBreaks(const std::vector<std::pair<const char*, std::string>>& paths) {
  for (const auto& [option, path] : paths)  // one case, one line: a runner (GNU parallel, a Slurm array) splits at newlines
    if (path.find_first_of("\n\r") != std::string::npos)
      throw std::invalid_argument(std::string(option) + " " + printable(path) + ": holds a line break, which would split "
                                  "each case's command over two lines of --list; rename it");
}

namespace {

int runSweepCommand(const SweepArgs& a) {
  if (a.list) refuseLineBreaks({{"the plan's path", a.plan}, {"--results", a.results}});
  const Plan plan = loadPlan(a.plan);
  if (a.list + !a.merge.empty() + !a.one_case.empty() > 1)
    throw std::invalid_argument("--list, --merge and --case: give at most one");
  if (!a.merge.empty() && !a.results.empty()) throw std::invalid_argument("--merge DIR reads DIR: give no --results");
  const std::string dir = !a.merge.empty() ? a.merge : a.results.empty() ? "results/" + plan.name : a.results;
  if (!a.merge.empty()) {
    if (!fs::is_directory(dir)) throw std::invalid_argument("--merge " + dir + ": no such folder");
    refuseSweepOverInputs(plan, a.plan, dir);
    return mergeInto(plan, dir);
  }
  if (!a.list) prepareFolder("--results", dir);
  if (!a.list) refuseSweepOverInputs(plan, a.plan, dir);
  if (!a.one_case.empty()) return runOneCase(plan, a.one_case, dir);
  return sweepPlan(plan, a.plan, dir, a.jobs, a.list);
}

}  // namespace

int sweepPlan(const Plan& plan, const std::string& plan_path, const std::string& dir, int jobs, bool list) {
  if (list) {
    for (const std::string& line : listCommands(plan, plan_path, dir)) std::printf("%s\n", line.c_str());
    return 0;
  }
  const int workers = jobs > 0 ? jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int errors = runSweep(plan, dir, workers);
  const int merged = mergeInto(plan, dir);
  if (errors) std::fprintf(stderr, "sweep: %d cases could not be run (their causes above)\n", errors);
  return errors || merged ? 1 : 0;
}

void addSweep(CLI::App& app) {
  auto* cmd = app.add_subcommand("sweep", "Run a plan's cases (scenes x methods x integrators x settings), resumably, "
                                          "and merge them: error against run time, cost against size (docs/sweep.md)");
  auto a = std::make_shared<SweepArgs>();
  cmd->add_option("plan", a->plan, "Plan file (eigenmass-plan/1; data/plans/)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--results", a->results, "Folder of the case results; default results/<plan name>/");
  CLI::Option* jobs = cmd->add_option("-j,--jobs", a->jobs, "Worker processes; default: every core (not with --list, --case, --merge: "
                                                            "none of them runs workers)")->check(CLI::Range(1, 1024));
  jobs->excludes(cmd->add_flag("--list", a->list, "Print one shell command per case (for GNU parallel or a Slurm array) and stop"));
  jobs->excludes(cmd->add_option("--case", a->one_case, "Run this one case (a name --list prints) and stop"));
  jobs->excludes(cmd->add_option("--merge", a->merge, "Merge the case results in this folder (as given to --results) and stop"));
  addProgressFlags(cmd);  // as benchmark and engine-study take them (sweep refused --progress)
  cmd->callback([a] { guarded([&] { return runSweepCommand(*a); }); });
}

}  // namespace em::cli
