#pragma once
// A plan made from a shipped template for one scene, written into its results
// folder so that it resumes, fans out and merges as any sweep: the engine
// study (`engine-study`) and the benchmark (`benchmark`) are such plans.
#include <string>

#include <nlohmann/json.hpp>

#include "io/urdf.hpp"

namespace em::cli {

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
