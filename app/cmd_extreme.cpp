// `eigenmass extreme`: every method through the extreme-case gallery (or any
// scenes given), a summary JSON, the Markdown page, and optionally a check
// of outcomes and failure kinds against a summary recorded earlier.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>

#include "app/cli.hpp"
#include "extreme/extreme.hpp"
#include "compare/provenance.hpp"
#include "compare/report.hpp"
#include "io/atomic_file.hpp"
#include "io/json_input.hpp"

namespace em::cli {

namespace {

namespace fs = std::filesystem;

struct ExtremeArgs {
  std::vector<std::string> paths = {"data/scenes/extreme"};
  std::vector<std::string> runs, methods = methodNames();
  std::string out_dir = "out/extreme", doc, expect;
  bool balance_inertia = false;
  RunArgs run;
  OutsideArgs outside;  ///< --plugin: a method from outside in every case
};

// Files as given; a folder stands for its .json and .urdf files, sorted.
std::vector<std::string> sceneFiles(const std::vector<std::string>& paths) {
  std::vector<std::string> files;
  for (const std::string& p : paths) {
    std::error_code ec;
    if (!fs::exists(p, ec)) throw std::runtime_error(p + ": no such file or folder");
    if (!fs::is_directory(p, ec)) {
      files.push_back(p);
      continue;
    }
    std::vector<std::string> inside;
    for (const auto& f : fs::directory_iterator(p))
      if (f.path().extension() == ".json" || f.path().extension() == ".urdf") inside.push_back(f.path().string());
    if (inside.empty()) throw std::runtime_error(p + ": no .json or .urdf scene in this folder");
    std::sort(inside.begin(), inside.end());
    files.insert(files.end(), inside.begin(), inside.end());
  }
  return files;
}

// Every case loaded (and --runs parsed) before anything runs.
std::vector<ExtremeCase> loadCases(const ExtremeArgs& a, const std::vector<std::string>& files) {
  std::vector<ExtremeSetting> runs;
  for (const std::string& r : a.runs) {
    try {
      runs.push_back(parseSetting(r));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("--runs: ") + e.what());
    }
  }
  std::vector<ExtremeCase> cases;
  for (const std::string& f : files) {
    UrdfOptions urdf;
    urdf.balance_inertia = a.balance_inertia;
    cases.push_back(loadExtremeCase(f, urdf));
    if (!runs.empty()) cases.back().settings = runs;
  }
  return cases;
}

void printCase(const ExtremeCaseResult& c) {
  for (const ExtremeRun& r : c.runs)
    for (const ExtremeEntry& e : r.entries)
      std::printf("%-22s %-18s %-18s %-7s %s\n", c.name.c_str(), r.setting.label().c_str(), e.method.c_str(),
                  outcomeName(e.outcome),
                  e.failure_kind == Failure::None
                      ? ""
                      : (std::string(failureName(e.failure_kind)) + " at " + gnum(e.failure_time) + " s").c_str());
}

int checkAgainst(const std::vector<ExtremeCaseResult>& results, const nlohmann::json& expected, const std::string& file) {
  const std::vector<std::string> diff = checkExpected(results, expected);
  if (diff.empty()) {
    std::printf("as expected: every outcome and failure kind matches %s\n", file.c_str());
    return 0;
  }
  for (const std::string& d : diff) std::printf("differs from %s: %s\n", file.c_str(), d.c_str());
  return 1;
}

int runExtreme(const ExtremeArgs& a, const CLI::App& cmd) {
  refuseDuplicates("--runs", a.runs);
  const std::vector<std::string> files = sceneFiles(a.paths);
  const std::vector<ExtremeCase> cases = loadCases(a, files);
  nlohmann::json expected;
  if (!a.expect.empty()) {
    expected = readJsonFile(a.expect, "--expect");
    try {
      validateExpected(expected);
    } catch (const std::invalid_argument& e) {
      throw std::runtime_error("--expect " + a.expect + ": " + e.what());
    }
  }
  std::vector<std::string> inputs = files;
  inputs.push_back(a.expect);
  for (const std::string& f : a.outside.files()) inputs.push_back(f);
  const std::string summary = (fs::path(a.out_dir) / "extreme.json").string();
  const std::string doc = a.doc.empty() ? (fs::path(a.out_dir) / "extreme.md").string() : a.doc;
  prepareOutput("--out-dir", summary, inputs);
  prepareOutput("--doc", doc, inputs);
  // A scene given twice, two scenes of one name, --doc onto a report: refused, not overwritten.
  std::vector<std::pair<std::string, std::string>> outputs = {{"--out-dir", summary}, {"--doc", doc}};
  for (size_t i = 0; i < files.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (std::error_code ec; fs::equivalent(files[i], files[j], ec))
        throw std::runtime_error(files[i] + ": listed twice (as " + files[j] + "): its cases would run twice into one report");
  for (const ExtremeCase& c : cases)
    for (const ExtremeSetting& s : c.settings) outputs.emplace_back(c.path, extremeReportPath(a.out_dir, c, s));
  refuseCollisions(outputs);
  ExtremeOptions opt;
  for (const std::string& m : a.methods) opt.methods.push_back(parseMethod(m));
  std::vector<std::string> added;
  for (const ExtremeCase& c : cases) added = a.outside.load(c.scene);  // probed at every case's initial state
  for (const std::string& m : added) opt.methods.push_back(parseMethod(m));
  refuseUnreadRunOptions(cmd, opt.methods, true);  // the gallery's settings include adaptive ones
  opt.grid = a.run.asked(cmd);
  a.run.applyTo(opt.options);
  opt.out_dir = a.out_dir;
  for (const ExtremeCase& c : cases) checkExtremeCase(c, opt);
  std::vector<ExtremeCaseResult> results;
  for (size_t i = 0; i < cases.size(); ++i) {
    std::fprintf(stderr, "[%zu/%zu] %s\n", i + 1, cases.size(), cases[i].path.c_str());
    results.push_back(runExtremeCase(cases[i], opt, progress));
    printCase(results.back());
  }
  const nlohmann::json j = extremeJson(results);
  writeJsonAtomic(j, summary);
  writeAtomic(doc, "--doc", [&](std::ostream& o) { o << extremeMarkdown(results, j["provenance"]); });
  std::printf("summary: %s\npage: %s\n", summary.c_str(), doc.c_str());
  return a.expect.empty() ? 0 : checkAgainst(results, expected, a.expect);
}

}  // namespace

void addExtreme(CLI::App& app) {
  auto* cmd = app.add_subcommand("extreme", "Run every method through the extreme-case gallery (or the scenes given): "
                                            "outcome, failure kind and diagnostics per case, a summary and a page");
  auto a = std::make_shared<ExtremeArgs>();
  cmd->add_option("scenes", a->paths, "Scene files or folders of them (.json, .urdf)")->capture_default_str();
  cmd->add_option("--runs", a->runs,
                  "Integrator settings for every case, comma-separated integrator:dt-or-tol (rk4:1e-3,rk8pd:1e-10); "
                  "default: each scene's x-extreme.runs, else rk4:1e-3,rk8pd:1e-10")
      ->delimiter(',');
  cmd->add_option("--methods", a->methods, helpWithNames("Methods, comma-separated", methodNames()))
      ->delimiter(',')
      ->check(methodValidator())
      ->capture_default_str();
  cmd->add_option("--out-dir", a->out_dir, "Folder of the full reports and the summary extreme.json")->capture_default_str();
  cmd->add_option("--doc", a->doc, "Markdown page to write; default <out-dir>/extreme.md");
  cmd->add_option("--expect", a->expect,
                  "A summary recorded earlier (extreme.json): exit 1 and list every outcome or failure kind that differs");
  cmd->add_flag("--balance-inertia", a->balance_inertia, "URDF: repair triangle-inequality violations (docs/urdf.md)");
  addRunOptions(cmd, a->run, "Common output grid (s)");
  addOutsideOptions(cmd, a->outside, false);
  cmd->callback([cmd, a] { guarded([&] { return runExtreme(*a, *cmd); }); });
}

}  // namespace em::cli
