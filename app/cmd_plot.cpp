// `eigenmass plot`: the figures of a compare report, a precision file, a
// trajectory, a sweep's results folder or an extreme summary (docs/figures.md).
// The input and the output folder are checked here, before anything is drawn;
// tools/plot.py draws with Debian's python3-matplotlib into a temporary folder,
// and each figure is then moved into --out by writeAtomic (the rules of every
// output: never an input, a device written into, a link followed, never half a file).
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <regex>
#include <set>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "io/shipped.hpp"
#include "io/atomic_file.hpp"
#include "io/json_input.hpp"
#include "io/scene_json.hpp"
#include "sweep/sweep.hpp"

namespace em::cli {

namespace {

namespace fs = std::filesystem;

struct PlotArgs {
  std::string input, out, format = "png", csv_dir;
};

// The interpreter with Debian's matplotlib (`python3` on the PATH may be another);
// EIGENMASS_PYTHON replaces it (the tests name a missing one).
std::string python() {
  const char* p = std::getenv("EIGENMASS_PYTHON");
  return p && *p ? p : "/usr/bin/python3";
}

// Run argv[0] with argv, its standard output discarded (and its errors too when
// `quiet`); its exit status, -1 when it could not run.
int runProgram(const std::vector<std::string>& argv, bool quiet) {
  std::cout.flush();
  std::fflush(stdout);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    // The child ends with its parent (SIGTERM; plot.py then removes its scratch
    // folder): an interrupted plot leaves no orphan drawing into /tmp.
    if (!dieWithParent(parent, SIGTERM)) _exit(143);  // the parent died before prctl
    std::FILE* null = std::fopen("/dev/null", "w");
    if (null) {
      dup2(fileno(null), 1);
      if (quiet) dup2(fileno(null), 2);
    }
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  endOnInterrupt(pid);  // an interrupt ends it and waits for it before the scratch folder goes
  int status = 0;
  const pid_t waited = waitpid(pid, &status, 0);
  releaseOnInterrupt(pid);
  if (waited < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// The file's "format" key, "" when it has none.
std::string formatOf(const nlohmann::json& j) {
  return j.is_object() && j.contains("format") && j["format"].is_string() ? j["format"].get<std::string>() : "";
}

// A name read from the input that will name figure files (a report's scene,
// a sweep's plan): refused unless it is a name a scene may have, so that no
// figure can be written outside --out (tools/plot.py checks every name it reads too).
void requireFigureName(const nlohmann::json& v, const std::string& where) {
  if (!v.is_string() || !isSceneName(v.get<std::string>()))
    throw std::runtime_error(where + " is " + printable(v.dump(), 60) + ": a name read from a file must be letters, "
                             "digits, '_' and '-' (1 to 64), since it names the figures; nothing drawn");
}

// The first sweep case file of a results folder names its plan; the merged CSV must be there.
void checkResults(const std::string& dir) {
  // Every JSON file is read here, so that a corrupt one is named (issue 53 item 15), and the
  // cases must be of one plan: two studies in one folder would draw one, silently (item 18).
  std::set<std::string> plans;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".json") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    const nlohmann::json j = readJsonFile(file.string(), "case");
    if (formatOf(j) != "eigenmass-sweep-case/1" || !j.contains("plan")) continue;
    requireFigureName(j["plan"], file.string() + ": key plan");
    plans.insert(j["plan"].get<std::string>());
  }
  if (plans.empty()) throw std::runtime_error(dir + ": not a sweep's results folder (no eigenmass-sweep-case/1 file)");
  if (plans.size() > 1)
    throw std::runtime_error(dir + ": the cases of " + std::to_string(plans.size()) + " plans (" + joined({plans.begin(), plans.end()}) +
                             "): one results folder per plan (sweep --results, engine-study --results)");
  const std::string plan = *plans.begin();
  if (!fs::exists(fs::path(dir) / (plan + ".csv")))
    throw std::runtime_error(dir + ": no merged " + plan + ".csv (run `eigenmass sweep PLAN --merge " + dir + "` first)");
}

// A trajectory CSV (simulate --out) is drawn with its sidecar, which says how it was made.
// A CSV without one (another simulator's, a recorded run) is drawn as its columns against t.
void checkTrajectory(const std::string& csv) {
  const std::string meta = csv + ".json";
  if (!fs::exists(csv)) throw std::runtime_error(csv + ": no such trajectory (its sidecar " + meta + " names it)");
  const std::string text = readFile(csv, "trajectory");
  const size_t header_end = text.find('\n');
  if (header_end == std::string::npos || text.find_first_not_of("\n", header_end) == std::string::npos)
    throw std::runtime_error(csv + ": no sample (a trajectory CSV has a header line and a line per sample)");
  if (!fs::exists(meta)) {
    if (text.rfind("t,", 0) != 0 && text.find("\nt,") == std::string::npos)
      throw std::runtime_error(csv + ": no sidecar " + meta + ", and no header line starting 't,' (time, then the columns drawn)");
    return;
  }
  if (formatOf(readJsonFile(meta, "trajectory metadata")) != "eigenmass-trajectory-meta/1")
    throw std::runtime_error(meta + ": not a trajectory's sidecar (key 'format' is not 'eigenmass-trajectory-meta/1')");
}

// What the input is: a kind tools/plot.py draws (docs/figures.md); the input it reads in `a.input`.
std::string kindOf(PlotArgs& a) {
  std::error_code ec;
  if (fs::is_directory(a.input, ec)) {
    checkResults(a.input);
    return "sweep";
  }
  const std::string ext = fs::path(a.input).extension().string();
  if (ext == ".csv") {
    checkTrajectory(a.input);
    return "trajectory";
  }
  const nlohmann::json j = readJsonFile(a.input, "report");
  const std::string format = formatOf(j);
  if (format == "eigenmass-report/1" && j.contains("series")) {
    requireFigureName(j.contains("scene") && j["scene"].is_object() ? j["scene"].value("name", nlohmann::json()) : nlohmann::json(),
                      a.input + ": key scene.name");
    return "report";
  }
  if (format == "eigenmass-report/1") throw std::runtime_error(a.input + ": key 'series' not found (a report without its series)");
  if (format == "eigenmass-extreme/1" && j.contains("cases")) return "extreme";
  if (format == "eigenmass-precision/1" && j.contains("points")) {
    requireFigureName(j.value("scene", nlohmann::json()), a.input + ": key scene");
    return "precision";
  }
  if (format == "eigenmass-trajectory-meta/1") {  // the sidecar given: draw its CSV
    a.input = a.input.substr(0, a.input.size() - std::string(".json").size());
    checkTrajectory(a.input);
    return "trajectory";
  }
  throw std::runtime_error(a.input + ": not a report, a precision file, an extreme summary, a trajectory or a results "
                           "folder (key 'format' is '" + printable(format, 40) + "')");
}

// Beside the input: out/p5.report.json -> out/p5.report.figures, out/x.csv -> out/x.figures;
// results/paper -> results/paper/figures.
std::string defaultOut(const std::string& input, const std::string& kind) {
  if (kind == "sweep") return (fs::path(input) / "figures").string();
  fs::path p(input);
  return (p.parent_path() / (p.stem().string() + ".figures")).string();
}

void checkPython() {
  const std::string py = python();
  if (runProgram({py, "-c", "import matplotlib"}, true) != 0)
    throw std::runtime_error("plot: " + py + " cannot import matplotlib: install Debian's python3-matplotlib "
                             "(apt-get install python3-matplotlib)");
}

// A private folder in $TMPDIR (else /tmp) for the script's figures, removed
// however the command ends: on return or a throw here, on SIGINT or SIGTERM
// by the interrupt handler (removeOnInterrupt).
struct ScratchFolder {
  fs::path path;
  ScratchFolder() {
    const char* env = std::getenv("TMPDIR");
    const std::string base = env && *env ? env : "/tmp";
    std::string tmpl = (fs::path(base) / "eigenmass-plot-XXXXXX").string();
    if (!mkdtemp(tmpl.data()))
      throw std::runtime_error("plot: cannot make a temporary folder in " + base + (env && *env ? " (TMPDIR)" : "") + ": " +
                               std::strerror(errno));
    path = tmpl;
    removeOnInterrupt(path.string());
  }
  ~ScratchFolder() {
    removeOnInterrupt("");
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// Every method's colour and every integrator's marker, from the registry:
// one per method in every figure. A method from outside (a plugin, a
// recorded run) is not in this process's registry: a report keeps its colour.
// Whose route each method is, and the integrators that own their routes, as
// the tables count them (routeOwner, benchmarkOwner): the figures name no
// engine or owner of their own.
std::string figureStyle(const std::string& input, const std::string& kind) {
  nlohmann::json colours = nlohmann::json::object(), markers = nlohmann::json::object();
  nlohmann::json owners = nlohmann::json::object(), integrator_owners = nlohmann::json::object();
  for (const MethodInfo& m : methodTable()) colours[m.name] = methodColour(m.id), owners[m.name] = methodOwner(m.id);
  if (kind == "report")
    for (const nlohmann::json& m : readJsonFile(input, "report").value("methods", nlohmann::json::array()))
      if (m.contains("colour") && m["colour"].is_string() && std::regex_match(m["colour"].get<std::string>(), std::regex("#[0-9a-fA-F]{6}|[a-z:]{1,32}")) &&
          m.contains("name") && m["name"].is_string())
        colours[m["name"].get<std::string>()] = m["colour"];
  for (const IntegratorInfo& i : integratorTable()) {
    markers[i.name] = i.marker ? i.marker : ".";
    if (routeOwningIntegrator(i)) integrator_owners[i.name] = i.name;
  }
  return nlohmann::json{{"colours", colours},
                        {"markers", markers},
                        {"owners", owners},
                        {"integrator_owners", integrator_owners},
                        {"in_house_owner", kInHouseOwner}}
      .dump();
}

// --csv-dir must hold this report's runs: read only where the report keeps no
// coordinate series, and refused when its reference is another run's.
void checkCsvDir(const std::string& report, const std::string& dir) {
  const nlohmann::json rep = readJsonFile(report, "report");
  if (rep["series"].contains("coordinate"))
    throw std::invalid_argument("--csv-dir: " + report + " keeps its coordinate series; the folder would not be read");
  const std::string csv = (fs::path(dir) / "reference.csv").string();
  if (!fs::exists(csv)) throw std::runtime_error("--csv-dir " + dir + ": no reference.csv (the folder compare --csv-dir wrote)");
  const nlohmann::json meta = readJsonFile(csv + ".json", "trajectory metadata");
  const nlohmann::json& ref = rep["reference"];
  const auto differs = [&](const char* key, const nlohmann::json& mine) { return !meta.contains(key) || meta[key] != mine; };
  for (const auto& [key, mine] : {std::pair<const char*, nlohmann::json>{"scene", rep["scene"]["name"]},
                                  {"method", ref["method"]}, {"integrator", ref["integrator"]},
                                  {"tolerance", ref["tolerance"]}, {"t_end", rep["options"]["t_end"]},
                                  {"output_dt", rep["options"]["output_dt"]}})
    if (differs(key, mine))
      throw std::invalid_argument("--csv-dir " + dir + ": another run's trajectories (reference.csv.json's " + key + " is " +
                                  printable(meta.value(key, nlohmann::json()).dump(), 40) + ", the report's " +
                                  printable(mine.dump(), 40) + ")");
  // Each method's CSV is drawn under the report's legend ("dt 0.001"): it must be that run (issue 53 item 14).
  if (!rep.contains("methods") || !rep["methods"].is_array()) return;
  for (const nlohmann::json& m : rep["methods"]) {
    if (!m.is_object() || !m.contains("name") || !m["name"].is_string()) continue;
    const std::string name = m["name"];
    if (!isSceneName(name)) continue;  // plot refuses such a name itself, before it reads any file
    const fs::path side = fs::path(dir) / (name + ".csv.json");
    if (!fs::exists(side)) continue;
    const nlohmann::json run = readJsonFile(side.string(), "trajectory metadata");
    for (const char* key : {"method", "integrator", "dt", "tolerance"}) {
      const nlohmann::json mine = key == std::string("method") ? m["name"] : m.value(key, nlohmann::json());
      if (mine.is_null()) continue;  // a tolerance run has no dt, a fixed-step one no tolerance
      if (!run.contains(key) || run[key] != mine)
        throw std::invalid_argument("--csv-dir " + dir + ": another run's trajectories (" + name + ".csv.json's " + key + " is " +
                                    printable(run.value(key, nlohmann::json()).dump(), 40) + ", the report's " +
                                    printable(mine.dump(), 40) + ")");
    }
  }
}

int runPlot(PlotArgs a) {
  const std::string kind = kindOf(a);
  if (!a.csv_dir.empty()) {
    if (kind != "report") throw std::invalid_argument("--csv-dir: only a compare report's trajectories are drawn from it");
    checkCsvDir(a.input, a.csv_dir);
  }
  if (a.out.empty()) a.out = defaultOut(a.input, kind);
  // The folders --out makes are removed again, while empty, when nothing is drawn (issue 73's doubtful list:
  // a refused plot left an empty --out folder behind).
  fs::path made = fs::absolute(a.out).lexically_normal();
  while (!made.parent_path().empty() && made.parent_path() != made && !fs::exists(made.parent_path())) made = made.parent_path();
  const bool fresh = !fs::exists(made);
  prepareFolder("--out", a.out);
  struct EmptyFoldersGone {
    fs::path leaf, top;
    ~EmptyFoldersGone() {
      std::error_code ec;
      for (fs::path p = leaf; !top.empty(); p = p.parent_path()) {
        if (!fs::is_directory(p, ec) || !fs::is_empty(p, ec) || !fs::remove(p, ec)) break;  // remove takes an empty folder only
        if (p == top) break;
      }
    }
  } gone{fresh ? fs::absolute(a.out).lexically_normal() : fs::path(), fresh ? made : fs::path()};
  checkPython();
  const ScratchFolder tmp;
  std::vector<std::string> argv = {python(), shippedFile("tools/plot.py", EM_SOURCE_DIR), kind, a.input, tmp.path.string(), a.format,
                                   "--style", figureStyle(a.input, kind)};
  if (!a.csv_dir.empty()) argv.insert(argv.end(), {"--csv-dir", a.csv_dir});
  const int status = runProgram(argv, false);
  if (status == 2 && fs::exists(tmp.path / "error.txt"))  // the input's shape is not its format's: its one line
    throw std::runtime_error(printable(readFile((tmp.path / "error.txt").string(), "error"), 300));
  if (status != 0) throw std::runtime_error("plot: drawing " + a.input + " failed (tools/plot.py exit " + std::to_string(status) + ")");
  std::vector<fs::path> figures;
  for (const auto& e : fs::directory_iterator(tmp.path)) figures.push_back(e.path());
  std::sort(figures.begin(), figures.end());
  for (const fs::path& f : figures) {
    const std::string to = (fs::path(a.out) / f.filename()).string();
    prepareOutput("--out", to, {a.input, a.input + ".json", a.csv_dir});
    const std::string bytes = readFile(f.string(), "figure");
    writeAtomic(to, "figure", [&](std::ostream& o) { o << bytes; });
    std::cout << to << "\n";
  }
  return 0;
}

}  // namespace

void addPlot(CLI::App& app) {
  auto* cmd = app.add_subcommand("plot", "Draw the figures of a compare report, a precision file, a trajectory, a sweep's "
                                         "results folder or an extreme summary (docs/figures.md; needs Debian's python3-matplotlib)");
  auto a = std::make_shared<PlotArgs>();
  cmd->add_option("input", a->input, "REPORT.json (compare --out), PRECISION.json (precision --out), a trajectory X.csv "
                                     "(simulate --out, with its X.csv.json), RESULTS_DIR (sweep) or an extreme summary")
      ->required();
  cmd->add_option("--out", a->out, "Folder for the figures; default: beside the input (X.report.figures/, RESULTS_DIR/figures/)");
  cmd->add_option("--format", a->format, "png (default), svg or pdf (vector figures for papers)")
      ->check(CLI::IsMember({"png", "svg", "pdf"}));
  cmd->add_option("--csv-dir", a->csv_dir, "compare --csv-dir's folder: the coordinate figure from its trajectories "
                                           "(for reports that keep no coordinate series)");
  cmd->callback([a] { guarded([&] { return runPlot(*a); }); });
}

}  // namespace em::cli
