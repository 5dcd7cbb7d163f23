#include "compare/cli.hpp"

#include <cstdio>
#include <filesystem>

namespace em::cli {

namespace {
int g_exit = 0;
}  // namespace

int exitCode() { return g_exit; }

void guarded(const std::function<int()>& body) {
  try {
    g_exit = body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "eigenmass: error: %s\n", e.what());
    g_exit = 2;
  }
}

void ensureParentDir(const std::string& path) {
  const auto dir = std::filesystem::path(path).parent_path();
  if (!dir.empty()) std::filesystem::create_directories(dir);
}

void progress(const std::string& what) { std::fprintf(stderr, "running %s ...\n", what.c_str()); }

CLI::Validator methodValidator() { return CLI::IsMember(methodNames()); }
CLI::Validator integratorValidator() { return CLI::IsMember(integratorNames()); }
CLI::Validator integratorValidator(Engine engine) { return CLI::IsMember(integratorNames(engine)); }

std::string helpWithNames(const std::string& text, const std::vector<std::string>& names) {
  return text + ": " + joined(names);
}

}  // namespace em::cli
