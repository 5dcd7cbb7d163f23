#include "compare/provenance.hpp"

#include "reference/engine.hpp"

#include <chrono>
#include <ctime>
#include <fstream>
#include <thread>

#include <Eigen/Core>
#include <gsl/gsl_version.h>

// Set by CMake for this file only (CMakeLists.txt): a new commit rebuilds one file.
#ifndef EM_VERSION
#define EM_VERSION "unknown"
#endif
#ifndef EM_GIT_COMMIT
#define EM_GIT_COMMIT "unknown"
#endif
#ifndef EM_SIMBODY_VERSION
#define EM_SIMBODY_VERSION "unknown"
#endif
#ifndef EM_CXX_FLAGS
#define EM_CXX_FLAGS "unknown"
#endif

namespace em {

namespace {

std::string g_command_line;

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

std::string utcNow() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  return buf;
}

// An argument as a shell would need it: quoted when it holds anything but safe characters.
std::string shellWord(const std::string& a) {
  if (!a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./=,:+") ==
                        std::string::npos)
    return a;
  std::string q = "'";
  for (char c : a) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string eigenVersion() {
  return std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
         std::to_string(EIGEN_MINOR_VERSION);
}

// Every engine's library by its engine's name, then the in-house solver's.
nlohmann::json libraries() {
  nlohmann::json l = {{"eigen", eigenVersion()}, {"gsl", GSL_VERSION}, {"urdfdom", EM_URDFDOM_VERSION}};
  for (const EngineRow& r : engineRows()) l[r.info.name] = r.code.version();
  return l;
}

}  // namespace

void setCommandLine(int argc, char** argv) {
  g_command_line.clear();
  for (int i = 0; i < argc; ++i) g_command_line += (i ? " " : "") + shellWord(argv[i]);
}

nlohmann::json provenance() {
  return {{"command_line", g_command_line},
          {"eigenmass_version", EM_VERSION},
          {"git_commit", EM_GIT_COMMIT},
          {"libraries", libraries()},
          {"compiler", __VERSION__},
          {"flags", EM_CXX_FLAGS},
          {"cpu", cpuModel()},
          {"cores", std::thread::hardware_concurrency()},
          {"date_utc", utcNow()}};
}

std::string versionText() {
  std::string engines;
  for (const EngineRow& r : engineRows()) engines += std::string(engines.empty() ? "" : ", ") + r.info.name + " " + r.code.version();
  return std::string("eigenmass ") + EM_VERSION + " (commit " + EM_GIT_COMMIT + "); engines: " + engines + "; Eigen " +
         eigenVersion() + ", GSL " + GSL_VERSION + ", liburdfdom " + EM_URDFDOM_VERSION + "; " + __VERSION__;
}

nlohmann::json sceneSourceJson(const SceneSource& s) {
  nlohmann::json j = {{"file", s.file}, {"format", s.format}, {"sha256", s.sha256}, {"import_notes", s.notes}};
  if (s.assembly)
    j["assembly"] = {{"gap_before", s.assembly->gap},         {"velocity_gap_before", s.assembly->velocity_gap},
                     {"max_change_q", s.assembly->moved_q},   {"max_change_u", s.assembly->moved_u},
                     {"gauss_newton_steps", s.assembly->iterations}};
  return j;
}

}  // namespace em
