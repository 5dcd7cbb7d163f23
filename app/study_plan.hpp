#pragma once
// A plan made from a shipped template for one scene, written into its results
// folder so that it resumes, fans out and merges as any sweep: the engine
// study (`engine-study`) and the benchmark (`benchmark`) are such plans.
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "io/urdf.hpp"

namespace em::cli {

/// What every subcommand that runs a template plan as a sweep takes.
struct TemplatePlanArgs {
  std::string results, plan;
  double t_end = 0;  ///< 0: the plan's (the problem's)
  int jobs = 0;
  bool list = false;
};
/// Each option's help, the subcommand's own words.
struct TemplatePlanHelp {
  const char *t_end, *plan, *results, *list;
};
/// Its options, in this order: --t-end, --plan, --results, -j/--jobs and --list (which excludes --jobs).
void addTemplatePlanOptions(CLI::App* cmd, TemplatePlanArgs& a, const TemplatePlanHelp& help);

/// The template's lines, reference and tables on this one scene (its import options kept), named `name`.
nlohmann::json templatePlan(const nlohmann::json& tmpl, const std::string& scene_path, const UrdfOptions& urdf,
                            const std::string& name, const std::string& description);

/// Where the plan goes in the results folder: `<dir>/<name>.plan.json`.
std::string templatePlanPath(const nlohmann::json& plan, const std::string& dir);

/// Check the plan (its errors name `named`, the template the user gave), make
/// the folder and write the plan into it. A plan written there before by
/// another run, or a file there that is no plan, is never replaced. Returns its path.
std::string writeTemplatePlan(const nlohmann::json& plan, const std::string& dir, const std::string& named,
                              const std::string& results_option);

}  // namespace em::cli
