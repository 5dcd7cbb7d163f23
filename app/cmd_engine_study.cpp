// `eigenmass engine-study SCENE`: which engine for this robot. Every engine
// and in-house route of the shipped study plan (data/plans/engines.json) on
// one scene or URDF, against its reference, as a sweep: the plan it runs is
// written into the results folder, so the study resumes, fans out (--list,
// GNU parallel, Slurm) and merges like any sweep (docs/engines.md).
#include <cstdio>
#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/cli.hpp"
#include "io/atomic_file.hpp"
#include "io/json_input.hpp"
#include "io/scene_json.hpp"
#include "io/shipped.hpp"
#include "sweep/sweep.hpp"

namespace em::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct StudyArgs {
  SceneArg scene;
  std::string results, plan;
  double t_end = 0;
  int jobs = 0;
  bool list = false;
};

// The study plan of one scene: the template's lines, reference and tables, this scene and its import options.
json studyPlan(const StudyArgs& a, const json& tmpl, const std::string& name) {
  json p = tmpl;
  json scene = {{"file", fs::absolute(a.scene.path).lexically_normal().string()}};
  if (a.scene.urdf.balance_inertia) scene["balance_inertia"] = true;
  if (a.scene.urdf.floating_base) scene["floating_base"] = true;
  if (!a.scene.urdf.lock_joints.empty()) scene["lock_joint"] = a.scene.urdf.lock_joints;
  p["scenes"] = json::array({scene});
  p["name"] = name;
  p["description"] = "Every engine and in-house route of " + fs::path(a.plan).filename().string() + " on " +
                     fs::path(a.scene.path).filename().string() + ", written by `eigenmass engine-study`.";
  if (a.t_end > 0) p["t_end"] = a.t_end;
  return p;
}

// Where the study's plan goes in the results folder.
std::string studyPlanPath(const json& plan, const std::string& dir) {
  return (fs::path(dir) / (plan.at("name").get<std::string>() + ".plan.json")).string();
}

// Write the study's plan (checked before: checkStudyPlan) into the results
// folder; one written before by another study, or a file there that is no
// plan, is never replaced.
std::string writeStudyPlan(const json& plan, const std::string& dir) {
  const std::string path = studyPlanPath(plan, dir);
  const std::string text = plan.dump(2) + "\n";
  if (fs::exists(path)) {
    const std::string there = readFile(path, "study plan");
    if (there == text) return path;
    try {
      parsePlan(there, path, path);
    } catch (const std::exception& e) {
      throw std::invalid_argument("--results " + dir + ": holds " + path + ", which is not a readable plan (" + std::string(e.what()) +
                                  "); remove it or choose another folder");
    }
    throw std::invalid_argument("--results " + dir + ": holds " + path + ", the plan of another study (other options, "
                                "another template); choose another folder or remove it");
  }
  writeAtomic(path, "study plan", [&](std::ostream& o) { o << text; });
  return path;
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
  const json study = studyPlan(a, tmpl, name);
  // The plan is checked before any file or folder is written: its errors name the template (--plan), not a copy.
  parsePlan(study.dump(2) + "\n", studyPlanPath(study, dir), "--plan " + a.plan + " (the study's plan made from it)");
  prepareFolder("--results", dir);
  const std::string path = writeStudyPlan(study, dir);
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
  cmd->add_option("--t-end", a->t_end, "Horizon T, s; default the study plan's")->check(positiveFinite());
  cmd->add_option("--plan", a->plan, "The study's template plan: its lines, reference and tables (default the shipped "
                                     "data/plans/engines.json); its scenes are replaced by SCENE")
      ->check(CLI::ExistingFile);
  cmd->add_option("--results", a->results, "Folder of the case results and of the plan written for them; default "
                                           "results/engine-study-<scene stem>/");
  CLI::Option* jobs = cmd->add_option("-j,--jobs", a->jobs, "Worker processes; default: every core (not with --list: it runs "
                                                            "none)")->check(CLI::Range(1, 1024));
  jobs->excludes(cmd->add_flag("--list", a->list, "Write the plan, print one shell command per case (GNU parallel, a Slurm array) and "
                                                  "stop; `sweep PLAN --merge DIR` merges them"));
  cmd->callback([a] { guarded([&] { return runStudy(*a); }); });
}

}  // namespace em::cli
