// `eigenmass benchmark [PROBLEM...]`: the field's benchmark (IFToMM's A01-A05,
// Andrews' squeezer) run by every engine and in-house route: for each problem
// (a scene with a "benchmark" key) a plan from the shipped template
// (data/plans/benchmark.json) on the problem's horizon and output steps,
// run as a sweep in its own folder (resumes, --list for GNU parallel and
// Slurm, merges), then one summary across the problems (docs/benchmark.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "app/study_plan.hpp"
#include "io/atomic_file.hpp"
#include "io/json_input.hpp"
#include "io/scene.hpp"
#include "io/shipped.hpp"
#include "solver/text.hpp"
#include "sweep/sweep.hpp"

namespace em::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct BenchArgs : TemplatePlanArgs {
  std::vector<std::string> problems;
};

constexpr const char* kShippedProblems = "data/scenes/mechanisms";

constexpr TemplatePlanHelp kBenchHelp = {
    "Horizon T, s, up to each problem's own (a shorter run measures the output steps within it, said in the tables); "
    "default the problem's",
    "The routes' template plan (default the shipped data/plans/benchmark.json); its scenes, horizon and output step are "
    "each problem's",
    "Folder of the results: a subfolder per problem and benchmark.md; default results/benchmark/",
    "Write the plans, print one shell command per case (GNU parallel, a Slurm array) and stop; `sweep PLAN --merge DIR` "
    "merges each problem, and `benchmark` again writes the summary"};

// Every shipped scene that is a benchmark problem: its problem name and file, in file-name order.
std::vector<std::pair<std::string, std::string>> shippedProblems() {
  std::vector<std::pair<std::string, std::string>> out;
  const std::string dir = shippedFile(kShippedProblems, EM_SOURCE_DIR);
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    const Scene s = loadScene(f.string());
    if (s.benchmark) out.emplace_back(s.benchmark->problem, f.string());
  }
  return out;
}

// A PROBLEM argument: a scene file with a "benchmark" key, or a shipped problem's name.
std::string problemFile(const std::string& arg, const std::vector<std::pair<std::string, std::string>>& shipped) {
  for (const auto& [name, file] : shipped)
    if (name == arg) return file;
  if (fs::is_regular_file(arg)) return arg;
  std::vector<std::string> names;
  for (const auto& p : shipped) names.push_back(p.first);
  throw std::invalid_argument("PROBLEM '" + printable(arg, 60) + "': neither a shipped problem (" + joined(names) +
                              ") nor a scene file");
}

// A fixed step runs a whole number of steps per output step: the template's
// steps that do not (Andrews' 1 ms outputs and a 1e-2 s step) are left out of
// this problem's plan, each said on stderr and in the plan's description; a
// line left with none is dropped the same way.
void fitSteps(json& plan, const BenchmarkSpec& b) {
  const double out = b.outputStep();
  std::vector<std::string> left_out;
  json lines = json::array();
  for (json line : plan.at("lines")) {
    if (!line.contains("dt")) {
      lines.push_back(line);
      continue;
    }
    json kept = json::array();
    for (const json& dt : line["dt"]) {
      const double ratio = dt.is_number() ? out / dt.get<double>() : NAN;
      if (!(ratio >= 1 - 1e-9) || std::abs(ratio - std::round(ratio)) > 1e-9 * ratio) {
        left_out.push_back(line.value("methods", json()).dump() + " " + line.value("integrator", json("?")).dump() + " dt " + dt.dump());
        continue;
      }
      kept.push_back(dt);
    }
    if (kept.empty()) continue;
    line["dt"] = kept;
    lines.push_back(line);
  }
  plan["lines"] = lines;
  if (left_out.empty()) return;
  const std::string note = "Steps left out, not a whole number per output step of " + gnum(out) + " s: " + joined(left_out) + ".";
  std::fprintf(stderr, "benchmark: problem %s: %s\n", b.problem.c_str(), note.c_str());
  plan["description"] = plan["description"].get<std::string>() + " " + note;
}

struct Problem {
  std::string file, stem, dir, plan_path;
  Scene scene;
};

int runBenchmark(BenchArgs& a) {
  const auto shipped = shippedProblems();
  std::vector<Problem> problems;
  if (a.problems.empty())
    for (const auto& p : shipped) a.problems.push_back(p.first);
  const std::string root = a.results.empty() ? "results/benchmark" : a.results;
  if (a.list) refuseLineBreaks({{"--results", root}});
  // Every problem is read and checked before any file is written.
  for (const std::string& arg : a.problems) {
    Problem p;
    p.file = problemFile(arg, shipped);
    p.scene = loadScene(p.file);
    if (!p.scene.benchmark)
      throw std::invalid_argument(p.file + ": benchmark: missing (a problem's error measure, horizon, output steps and "
                                  "precision levels; docs/scene-format.md)");
    p.stem = fs::path(p.file).stem().string();
    if (!isSceneName(p.stem))
      throw std::invalid_argument(p.file + ": its file name's stem must be letters, digits, '_' or '-' (1 to 64): it names "
                                  "the problem's plan and cases; rename or copy the file");
    for (const Problem& q : problems)
      if (q.stem == p.stem) throw std::invalid_argument("PROBLEM " + arg + ": a second problem named '" + p.stem + "'");
    p.dir = (fs::path(root) / p.stem).string();
    problems.push_back(std::move(p));
  }
  if (a.plan.empty()) a.plan = shippedFile("data/plans/benchmark.json", EM_SOURCE_DIR);
  const json tmpl = readJsonFile(a.plan, "plan");
  std::vector<json> plans;
  for (const Problem& p : problems) {
    const BenchmarkSpec& b = *p.scene.benchmark;
    if (a.t_end > b.t_end * (1 + 1e-12))
      throw std::invalid_argument("--t-end: " + gnum(a.t_end) + " s beyond problem " + b.problem + "'s horizon " + gnum(b.t_end) + " s");
    // The horizon the user gave must hold whole output steps of the problem (issue 73, item 14: the
    // message blamed the template plan, which the user never gave).
    if (const double steps = a.t_end / b.outputStep(); a.t_end > 0 && std::abs(steps - std::round(steps)) > 1e-9 * steps)
      throw std::invalid_argument("--t-end: " + gnum(a.t_end) + " s is not a whole number of problem " + b.problem + "'s output steps (" +
                                  gnum(b.outputStep()) + " s)");
    json plan;
    try {
      plan = templatePlan(tmpl, p.file, {}, "benchmark-" + p.stem,
                          "Problem " + b.problem + " (" + fs::path(p.file).filename().string() + ") by every route of " +
                              fs::path(a.plan).filename().string() + ", written by `eigenmass benchmark`.");
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("--plan " + a.plan + ": " + e.what());
    }
    plan["t_end"] = a.t_end > 0 ? a.t_end : b.t_end;
    plan["output_dt"] = b.outputStep();
    fitSteps(plan, b);
    plans.push_back(plan);
  }
  prepareFolder("--results", root);
  int status = 0;
  std::vector<BenchmarkProblem> merged;
  for (size_t i = 0; i < problems.size(); ++i) {
    Problem& p = problems[i];
    p.plan_path = writeTemplatePlan(plans[i], p.dir, "--plan " + a.plan + " (problem " + p.stem + "'s plan made from it)", "--results");
    const Plan plan = loadPlan(p.plan_path);
    if (!a.list) refuseSweepOverInputs(plan, p.plan_path, p.dir);
    if (!a.list)
      std::fprintf(stderr, "benchmark: problem %s (%s, %d speeds), %zu cases in %s\n", p.scene.benchmark->problem.c_str(),
                   p.file.c_str(), p.scene.model.nu, planCases(plan).size(), p.dir.c_str());
    status |= sweepPlan(plan, p.plan_path, p.dir, a.jobs, a.list);
    if (a.list) continue;
    std::vector<std::string> missing;
    BenchmarkProblem bp{p.stem, *p.scene.benchmark, collectRecords(plan, p.dir, missing), false};
    bp.complete = missing.empty();
    if (bp.complete) {  // the summary's margins: its contenders timed in interleaved rounds (sweep.hpp, Interleaved)
      const std::vector<std::string> contenders = benchmarkContenders(bp.records, bp.scene, bp.spec);
      std::fprintf(stderr, "benchmark: problem %s: %zu runs timed over %d interleaved rounds for the margins\n",
                   p.scene.benchmark->problem.c_str(), contenders.size(), kInterleavedRounds);
      bp.interleaved = timeInterleaved(plan, contenders, p.dir, kInterleavedRounds);
    }
    merged.push_back(std::move(bp));
  }
  if (a.list) return status;
  const std::string summary = (fs::path(root) / "benchmark.md").string();
  std::string text = "## Summary\n\n" + benchmarkSummary(merged);
  for (const Problem& p : problems) {
    const fs::path md = fs::path(p.dir) / ("benchmark-" + p.stem + ".md");
    if (fs::exists(md)) text += readFile(md.string(), "merged tables") + "\n";
  }
  writeAtomic(summary, "benchmark summary", [&](std::ostream& o) { o << text; });
  std::fprintf(stderr, "benchmark: %zu problems; summary in %s\n", problems.size(), summary.c_str());
  return status;
}

}  // namespace

void addBenchmark(CLI::App& app) {
  auto* cmd = app.add_subcommand("benchmark", "The field's benchmark (IFToMM A01-A05, Andrews): every engine and in-house "
                                              "route to each problem's precision levels, CPU time and violation, as "
                                              "resumable sweeps (docs/benchmark.md)");
  auto a = std::make_shared<BenchArgs>();
  cmd->add_option("problem", a->problems, "Problems: shipped names (A01, A02, A02-N2, A03, A04, A05) or scene files with a "
                                          "\"benchmark\" key; default every shipped problem");
  addTemplatePlanOptions(cmd, *a, kBenchHelp);
  cmd->callback([a] { guarded([&] { return runBenchmark(*a); }); });
}

}  // namespace em::cli
