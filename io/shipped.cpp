#include "io/shipped.hpp"

#include <filesystem>

namespace em {

std::string shippedFile(const std::string& rel, const std::string& source_dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "eigenmass" / rel;
    if (fs::exists(installed, ec)) return installed.string();
  }
  return (fs::path(source_dir) / rel).string();
}

}  // namespace em
