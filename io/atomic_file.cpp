#include "io/atomic_file.hpp"

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>

namespace em {

namespace {

// The temporary being written, for the signal handler (async-signal-safe: a
// fixed buffer, a flag, unlink, signal, raise).
char g_tmp[4096];
volatile std::sig_atomic_t g_tmp_active = 0;

extern "C" void removeTemporaryAndDie(int sig) {
  if (g_tmp_active) ::unlink(g_tmp);
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

void installInterruptCleanup() {
  std::signal(SIGINT, removeTemporaryAndDie);
  std::signal(SIGTERM, removeTemporaryAndDie);
}

void writeAtomic(const std::string& path, const std::string& what, const std::function<void(std::ostream&)>& write) {
  // One temporary per process: sweep workers may write the same file at once
  // (a scene's reference, run by whichever case needs it first); the last rename wins.
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
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
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename the temporary " + what);
  }
}

}  // namespace em
