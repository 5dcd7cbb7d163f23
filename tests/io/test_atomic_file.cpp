// Atomic writes (io/atomic_file.cpp): a regular file is replaced whole; a
// device or FIFO is written into and stays what it was; a symbolic link is
// followed and kept. Devices are made with mknod in a temporary folder, never
// the machine's own.
#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "io/atomic_file.hpp"
#include "support.hpp"

using namespace em;
namespace fs = std::filesystem;

namespace {

struct TempDir {
  fs::path dir;
  TempDir() {
    std::string t = (fs::temp_directory_path() / "em-atomic-XXXXXX").string();
    dir = ::mkdtemp(t.data());
  }
  ~TempDir() { fs::remove_all(dir); }
  std::string operator/(const std::string& name) const { return (dir / name).string(); }
};

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void writeText(const std::string& path, const std::string& text) {
  writeAtomic(path, "text", [&](std::ostream& o) { o << text; });
}

bool isCharDevice(const std::string& path) {
  struct stat st;
  return ::lstat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

}  // namespace

TEST_CASE("a regular file is replaced whole, without a temporary left", "[atomic]") {
  TempDir t;
  const std::string f = t / "out.txt";
  writeText(f, "old");
  writeText(f, "new");
  CHECK(readAll(f) == "new");
  CHECK_FALSE(test::temporaryLeft(f));
}

TEST_CASE("a symbolic link is followed: its target is written, the link kept - a dangling one is refused", "[atomic]") {
  TempDir t;
  const std::string target = t / "target.txt", link = t / "link.txt";
  writeText(target, "old");
  fs::create_symlink(target, link);
  writeText(link, "new");
  CHECK(fs::is_symlink(link));
  CHECK(readAll(target) == "new");
  const std::string dangling = t / "dangling.txt";
  fs::create_symlink(t / "missing.txt", dangling);
  CHECK_THROWS_WITH(writeText(dangling, "x"), Catch::Contains("a symbolic link to a missing file"));
  CHECK_FALSE(fs::exists(t / "missing.txt"));
  CHECK(fs::is_symlink(dangling));
}

TEST_CASE("a FIFO is written into and stays a FIFO", "[atomic]") {
  TempDir t;
  const std::string fifo = t / "pipe";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  std::string got;
  std::thread reader([&] { got = readAll(fifo); });
  writeText(fifo, "through the pipe\n");
  reader.join();
  CHECK(got == "through the pipe\n");
  CHECK(fs::is_fifo(fifo));
  CHECK_FALSE(test::temporaryLeft(fifo));
}

TEST_CASE("a character device is written into, never replaced, and its write error is an error", "[atomic]") {
  TempDir t;
  const std::string null = t / "null", full = t / "full";
  // mknod needs CAP_MKNOD (root, CI); without it the FIFO case above still runs.
  if (::mknod(null.c_str(), S_IFCHR | 0600, makedev(1, 3)) != 0 || ::mknod(full.c_str(), S_IFCHR | 0600, makedev(1, 7)) != 0) {
    WARN("mknod not permitted here: the device cases are skipped");
    return;
  }
  writeText(null, "discarded");
  CHECK(isCharDevice(null));  // an atomic rename would have made it a regular file
  CHECK_THROWS_WITH(writeText(full, std::string(1 << 16, 'x')), Catch::Contains("write failed"));
  CHECK(isCharDevice(full));
}
