#include "io/atomic_file.hpp"

#include "solver/text.hpp"

#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <stdexcept>

namespace em {

namespace {

// The temporary being written, for the signal handler (async-signal-safe: a
// fixed buffer, a flag, unlink, signal, raise).
char g_tmp[4096];
volatile std::sig_atomic_t g_tmp_active = 0;
// A scratch folder and the child drawing into it (plot): the child is ended
// and waited for, then the folder, by then empty, removed (rmdir).
char g_folder[4096];
volatile std::sig_atomic_t g_folder_active = 0;
volatile pid_t g_children[kMaxChildren] = {};  // 0: a free slot

extern "C" void removeTemporaryAndDie(int sig) {
  if (g_tmp_active) ::unlink(g_tmp);
  // plot.py removes what it drew on SIGTERM, a worker its temporary; before their handlers, SIGTERM ends them.
  for (int i = 0; i < kMaxChildren; ++i)
    if (const pid_t child = g_children[i]; child > 0) ::kill(child, SIGTERM);
  for (int i = 0; i < kMaxChildren; ++i)
    if (const pid_t child = g_children[i]; child > 0)
      while (::waitpid(child, nullptr, 0) < 0 && errno == EINTR) {
      }
  if (g_folder_active) ::rmdir(g_folder);
  // One line, as every ending of the tool (write(2) is async-signal-safe).
  static const char kInt[] = "eigenmass: interrupted (SIGINT); no output was left half-written\n";
  static const char kTerm[] = "eigenmass: terminated (SIGTERM); no output was left half-written\n";
  const int fd = g_stderr_fd;  // stderr itself, not an engine's gathered messages
  if (sig == SIGINT) (void)!::write(fd, kInt, sizeof kInt - 1);
  else (void)!::write(fd, kTerm, sizeof kTerm - 1);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// Marks `tmp` as the file to remove on a signal while it exists.
struct TemporaryGuard {
  explicit TemporaryGuard(const std::string& tmp) {
    if (tmp.size() >= sizeof g_tmp) throw std::runtime_error(tmp + ": path too long");
    std::memcpy(g_tmp, tmp.c_str(), tmp.size() + 1);
    g_tmp_active = 1;
  }
  ~TemporaryGuard() { g_tmp_active = 0; }
};

}  // namespace

void removeOnInterrupt(const std::string& folder) {
  g_folder_active = 0;
  if (folder.empty()) return;
  if (folder.size() >= sizeof g_folder) throw std::runtime_error(folder + ": path too long");
  std::memcpy(g_folder, folder.c_str(), folder.size() + 1);
  g_folder_active = 1;
}

void endOnInterrupt(pid_t child) {
  for (int i = 0; i < kMaxChildren; ++i)
    if (g_children[i] == 0) {
      g_children[i] = child;
      return;
    }
  throw std::runtime_error("more than " + std::to_string(kMaxChildren) + " child processes at once");
}

void releaseOnInterrupt(pid_t child) {
  for (int i = 0; i < kMaxChildren; ++i)
    if (g_children[i] == child) g_children[i] = 0;
}

bool dieWithParent(pid_t parent, int sig) {
  for (int i = 0; i < kMaxChildren; ++i) g_children[i] = 0;  // the parent's, not this process's
  return ::prctl(PR_SET_PDEATHSIG, sig) == 0 && ::getppid() == parent;
}

void installInterruptCleanup() {
  std::signal(SIGINT, removeTemporaryAndDie);
  std::signal(SIGTERM, removeTemporaryAndDie);
}

namespace {

// Where `path` is written, and how: a regular file (or a new one) atomically;
// a device, FIFO or socket straight into it, never replaced; a symbolic link
// through to its target, the link kept.
struct Target {
  std::string path;
  bool through = false;  ///< write into the file as it is (not a regular file)
};

Target resolveTarget(const std::string& path) {
  struct stat st;
  if (::lstat(path.c_str(), &st) != 0) return {path, false};  // a new file
  std::string p = path;
  if (S_ISLNK(st.st_mode)) {
    if (::stat(path.c_str(), &st) != 0)
      throw std::runtime_error(path + ": a symbolic link to a missing file; give the file itself");
    // A link to a regular file: its target, atomically; to a device or a pipe
    // (/dev/stdout): through the link itself, which open() follows.
    if (S_ISREG(st.st_mode)) p = std::filesystem::canonical(path).string();
  }
  if (S_ISDIR(st.st_mode)) throw std::runtime_error(path + ": is a folder, not a file");
  return {p, !S_ISREG(st.st_mode)};
}

// Straight into a device or FIFO: its bytes go where the device sends them; a
// write error (/dev/full) is an error.
void writeThrough(const std::string& path, const std::string& what, const std::function<void(std::ostream&)>& write) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write the " + what);
  write(out);
  out.flush();
  if (!out) throw std::runtime_error(path + ": write failed");
}

}  // namespace

bool writesThrough(const std::string& path) { return resolveTarget(path).through; }

void writeAtomic(const std::string& path, const std::string& what, const std::function<void(std::ostream&)>& write) {
  const Target target = resolveTarget(path);
  if (target.through) return writeThrough(target.path, what, write);
  // One temporary per process: sweep workers may write the same file at once
  // (a scene's reference, run by whichever case needs it first); the last rename wins.
  const std::string tmp = target.path + ".tmp." + std::to_string(::getpid());
  TemporaryGuard guard(tmp);
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error(path + ": cannot write the " + what);
    write(out);
    out.flush();
    if (!out) {
      out.close();
      std::remove(tmp.c_str());
      throw std::runtime_error(path + ": write failed");
    }
  }
  if (std::rename(tmp.c_str(), target.path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename the temporary " + what);
  }
}

int finishStandardOutput(const char* program, int code) {
  std::cout.flush();
  const bool lost = !std::cout.good() || std::fflush(stdout) != 0 || std::ferror(stdout);
  if (!lost) return code;
  std::fprintf(stderr, "%s: error: standard output: write failed (full or closed)\n", program);
  return code == 0 ? 2 : code;
}

}  // namespace em
