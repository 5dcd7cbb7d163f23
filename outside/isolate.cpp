#include "outside/isolate.hpp"

#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

// The page parent and child share: how many beats, and the last beat's time.
struct Beat {
  std::atomic<unsigned long> count{0};
  std::atomic<double> t{0};
};

Beat* g_beat = nullptr;      // set in a child only
unsigned long g_beats = 0;   // the child's own count (one writer)

void writeAll(int fd, const std::string& s) {
  size_t done = 0;
  while (done < s.size()) {
    const ssize_t k = write(fd, s.data() + done, s.size() - done);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) _exit(4);
    done += static_cast<size_t>(k);
  }
}

// The child: run the work, send "ok\n" + its text or "error\n" + the message.
// It dies with its parent (SIGKILL when the parent exits by any path: a
// signal's handler, a crash, SIGKILL), so it never outlives it; init reaps it.
[[noreturn]] void child(const std::function<std::string()>& work, int fd, Beat* beat, pid_t parent) {
  if (!dieWithParent(parent, SIGKILL)) _exit(5);  // the parent already gone: before prctl took
  // The parent's handlers are the parent's: its cleanup, and a sanitizer's
  // report, which would turn a plugin's crash into an exit status.
  for (int sig : {SIGINT, SIGTERM, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) signal(sig, SIG_DFL);
  // What the plugin prints goes to standard error, a line at a time: eigenmass's standard output
  // (its tables, a JSON on /dev/stdout) stays its own, and a crash loses at most a partial line.
  std::fflush(stdout);
  dup2(STDERR_FILENO, STDOUT_FILENO);
  setvbuf(stdout, nullptr, _IOLBF, 0);
  g_beat = beat;
  std::string out;
  try {
    out = "ok\n" + work();
  } catch (const std::exception& e) {
    out = std::string("error\n") + e.what();
  }
  writeAll(fd, out);
  close(fd);
  std::fflush(stdout);  // the plugin's last partial line (the parent's buffers were flushed before the fork)
  _exit(0);  // no atexit handlers: they are the parent's
}

std::string signalText(int sig) {
  const char* name = sigabbrev_np(sig);
  return std::string("crashed (SIG") + (name ? name : std::to_string(sig).c_str()) + ")";
}

// Read the child's text until it closes its end, watching its beats.
void watch(pid_t pid, int fd, Beat* beat, double timeout_s, Isolated& r, bool& killed) {
  using clock = std::chrono::steady_clock;
  unsigned long seen = 0;
  auto last = clock::now();
  char buf[65536];
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    const int ready = poll(&p, 1, static_cast<int>(kPluginWatch * 1000));
    if (ready > 0) {
      const ssize_t k = read(fd, buf, sizeof buf);
      if (k > 0) {
        r.output.append(buf, static_cast<size_t>(k));
        continue;
      }
      if (k == 0) return;  // the child closed its end (it returned, or died)
      if (errno != EINTR) return;
    }
    const unsigned long now = beat->count.load();
    if (now != seen) {
      seen = now;
      last = clock::now();
    } else if (std::chrono::duration<double>(clock::now() - last).count() > timeout_s) {
      kill(pid, SIGKILL);
      killed = true;
      return;
    }
  }
}

}  // namespace

void isolatedBeat(double t) {
  if (!g_beat) return;
  g_beat->t.store(t, std::memory_order_relaxed);
  g_beat->count.store(++g_beats, std::memory_order_relaxed);
}

Isolated runIsolated(const std::function<std::string()>& work, double timeout_s) {
  void* page = mmap(nullptr, sizeof(Beat), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (page == MAP_FAILED) throw std::runtime_error(std::string("isolation: mmap: ") + std::strerror(errno));
  Beat* beat = new (page) Beat;
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error(std::string("isolation: pipe: ") + std::strerror(errno));
  std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("isolation: fork: ") + std::strerror(errno));
  if (pid == 0) {
    close(fds[0]);
    child(work, fds[1], beat, parent);
  }
  close(fds[1]);
  Isolated r;
  bool killed = false;
  watch(pid, fds[0], beat, timeout_s, r, killed);
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  r.beat = beat->count.load() > 0;
  r.t = beat->t.load();
  munmap(page, sizeof(Beat));
  if (killed) {
    r.failure = "no return within " + gnum(timeout_s) + " s (killed)";
  } else if (WIFSIGNALED(status)) {
    r.failure = signalText(WTERMSIG(status));
  } else if (WEXITSTATUS(status) != 0 || r.output.compare(0, 3, "ok\n") != 0) {
    r.failure = r.output.compare(0, 6, "error\n") == 0 ? r.output.substr(6)
                                                       : "ended with status " + std::to_string(WEXITSTATUS(status));
  } else {
    r.ok = true;
    r.output.erase(0, 3);
  }
  if (!r.ok) r.output.clear();
  return r;
}

}  // namespace em
