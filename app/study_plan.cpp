#include "app/study_plan.hpp"

#include <filesystem>
#include <stdexcept>

#include "app/cli.hpp"
#include "io/atomic_file.hpp"
#include "io/json_input.hpp"
#include "sweep/plan.hpp"

namespace em::cli {

namespace fs = std::filesystem;
using nlohmann::json;

void addTemplatePlanOptions(CLI::App* cmd, TemplatePlanArgs& a, const TemplatePlanHelp& help) {
  cmd->add_option("--t-end", a.t_end, help.t_end)->check(positiveFinite());
  cmd->add_option("--plan", a.plan, help.plan)->check(CLI::ExistingFile);
  cmd->add_option("--results", a.results, help.results);
  CLI::Option* jobs = cmd->add_option("-j,--jobs", a.jobs, "Worker processes; default: every core (not with --list: it runs "
                                                           "none)")->check(CLI::Range(1, 1024));
  jobs->excludes(cmd->add_flag("--list", a.list, help.list));
  addProgressFlags(cmd);  // issue 73, item 14: benchmark refused --no-progress
}

json templatePlan(const json& tmpl, const std::string& scene_path, const UrdfOptions& urdf, const std::string& name,
                  const std::string& description) {
  // A template is a plan: an object whose routes are its "lines" (issue 73, item 14: a scene or an
  // array given as --plan printed a raw json.exception).
  if (!tmpl.is_object()) throw std::invalid_argument("expected a plan: an object with \"format\": \"eigenmass-plan/1\" (docs/sweep.md)");
  if (tmpl.value("format", json()) == "eigenmass-scene/1") throw std::invalid_argument("a scene, not a plan (eigenmass-plan/1, docs/sweep.md)");
  if (tmpl.value("format", json()) != "eigenmass-plan/1") throw std::invalid_argument("format: expected \"eigenmass-plan/1\"");
  if (!tmpl.contains("lines") || !tmpl["lines"].is_array()) throw std::invalid_argument("lines: missing or not a list (the template's routes)");
  json p = tmpl;
  json scene = {{"file", fs::absolute(scene_path).lexically_normal().string()}};
  if (urdf.balance_inertia) scene["balance_inertia"] = true;
  if (urdf.floating_base) scene["floating_base"] = true;
  if (!urdf.lock_joints.empty()) scene["lock_joint"] = urdf.lock_joints;
  if (urdf.damping) scene["damping"] = true;
  if (urdf.ignore_friction) scene["ignore_friction"] = true;
  if (urdf.limits_restitution) scene["limits_restitution"] = *urdf.limits_restitution;
  if (!urdf.control_file.empty()) scene["control"] = fs::absolute(urdf.control_file).lexically_normal().string();
  p["scenes"] = json::array({scene});
  p["name"] = name;
  p["description"] = description;
  return p;
}

std::string templatePlanPath(const json& plan, const std::string& dir) {
  return (fs::path(dir) / (plan.at("name").get<std::string>() + ".plan.json")).string();
}

std::string writeTemplatePlan(const json& plan, const std::string& dir, const std::string& named, const std::string& results_option) {
  const std::string path = templatePlanPath(plan, dir);
  const std::string text = plan.dump(2) + "\n";
  // Checked before any file or folder is written: its errors name the template, not a copy.
  parsePlan(text, path, named);
  prepareFolder(results_option, dir);
  if (fs::exists(path)) {
    const std::string there = readFile(path, "study plan");
    if (there == text) return path;
    try {
      parsePlan(there, path, path);
    } catch (const std::exception& e) {
      throw std::invalid_argument(results_option + " " + dir + ": holds " + path + ", which is not a readable plan (" +
                                  std::string(e.what()) + "); remove it or choose another folder");
    }
    throw std::invalid_argument(results_option + " " + dir + ": holds " + path + ", the plan of another study (other options, "
                                "another template); choose another folder or remove it");
  }
  writeAtomic(path, "study plan", [&](std::ostream& o) { o << text; });
  return path;
}

}  // namespace em::cli
