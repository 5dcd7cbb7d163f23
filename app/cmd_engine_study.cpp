// `eigenmass engine-study SCENE`: which engine for this robot. Every engine
// and in-house route of the shipped study plan (data/plans/engines.json) on
// one scene or URDF, against its reference, as a sweep: the plan it runs is
// written into the results folder, so the study resumes, fans out (--list,
// GNU parallel, Slurm) and merges like any sweep (docs/engines.md).
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>

#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "app/study_plan.hpp"
#include "io/json_input.hpp"
#include "io/scene_json.hpp"
#include "io/shipped.hpp"
#include "solver/control.hpp"
#include "solver/text.hpp"
#include "sweep/sweep.hpp"

namespace em::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr TemplatePlanHelp kStudyHelp = {
    "Horizon T, s; default the study plan's",
    "The study's template plan: its lines, reference and tables (default the shipped data/plans/engines.json); its "
    "scenes are replaced by SCENE",
    "Folder of the case results and of the plan written for them; default results/engine-study-<scene stem>/",
    "Write the plan, print one shell command per case (GNU parallel, a Slurm array) and stop; `sweep PLAN --merge DIR` "
    "merges them"};

struct StudyArgs : TemplatePlanArgs {
  SceneArg scene;
};

// A sampled controller is sampled at step starts (docs/theory.md §18): the
// study keeps the fixed steps that divide its period, and its description
// says which it left out (a line left with none goes).
void keepStepsOfPeriod(const Model& m, json& study) {
  if (!m.has_control || !(m.control_period > 0)) return;
  std::set<double> dropped;
  json lines = json::array();
  for (json line : study["lines"]) {
    if (line.contains("dt")) {
      json kept = json::array();
      for (const json& dt : line["dt"])
        (stepsPerControlPeriod(m.control_period, dt.get<double>()) ? kept.push_back(dt) : void(dropped.insert(dt.get<double>())));
      if (kept.empty()) continue;
      line["dt"] = kept;
    }
    lines.push_back(line);
  }
  study["lines"] = lines;
  if (dropped.empty()) return;
  std::string which;
  for (double dt : dropped) which += (which.empty() ? "" : ", ") + gnum(dt);
  study["description"] = study["description"].get<std::string>() + " Steps that do not divide the controller's period " +
                         gnum(m.control_period) + " s are left out (" + which + " s): it is sampled at step starts.";
}

int runStudy(StudyArgs& a) {
  const Scene scene = a.scene.load();  // a bad scene is named as every command names it, before any file is written
  if (a.plan.empty()) a.plan = shippedFile("data/plans/engines.json", EM_SOURCE_DIR);
  const json tmpl = readJsonFile(a.plan, "plan");
  const std::string stem = fs::path(a.scene.path).stem().string();
  if (!isSceneName(stem))  // before any file is written: the stem names the study's plan and every case
    throw std::invalid_argument(a.scene.path + ": its file name's stem must be letters, digits, '_' or '-' (1 to 64): "
                                "it names the study's plan and cases; rename or copy the file");
  const std::string name = "engine-study-" + stem;
  const std::string dir = a.results.empty() ? "results/" + name : a.results;
  if (a.list) refuseLineBreaks({{"--results", dir}});
  json study;
  try {
    study = templatePlan(tmpl, a.scene.path, a.scene.urdf, name,
                         "Every engine and in-house route of " + fs::path(a.plan).filename().string() + " on " +
                             fs::path(a.scene.path).filename().string() + ", written by `eigenmass engine-study`.");
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("--plan " + a.plan + ": " + e.what());
  }
  if (a.t_end > 0) study["t_end"] = a.t_end;
  keepStepsOfPeriod(scene.model, study);
  const std::string path = writeTemplatePlan(study, dir, "--plan " + a.plan + " (the study's plan made from it)", "--results");
  const Plan plan = loadPlan(path);
  if (!a.list) refuseSweepOverInputs(plan, path, dir);
  std::fprintf(stderr, "engine-study: %s (%d speeds), %zu cases of %s\n", scene.source.file.c_str(), scene.model.nu,
               planCases(plan).size(), path.c_str());
  return sweepPlan(plan, path, dir, a.jobs, a.list);
}

}  // namespace

void addEngineStudy(CLI::App& app) {
  auto* cmd = app.add_subcommand("engine-study", "Which engine for this robot: every engine and in-house route at the "
                                                 "steps users run, against a reference, as a resumable sweep "
                                                 "(docs/engines.md)");
  auto a = std::make_shared<StudyArgs>();
  addSceneArg(cmd, a->scene);
  addTemplatePlanOptions(cmd, *a, kStudyHelp);
  cmd->callback([a] { guarded([&] { return runStudy(*a); }); });
}

}  // namespace em::cli
