#include "compare/progress.hpp"

#include <cstdio>
#include <unistd.h>

namespace em {

namespace {
ProgressMode g_mode = ProgressMode::Auto;  // the CLI's choice, set before any run
constexpr double kTerminalRefreshS = 0.25;  // a terminal line is redrawn at most this often
}  // namespace

void setProgressMode(ProgressMode mode) { g_mode = mode; }
ProgressMode progressMode() { return g_mode; }

ProgressMeter::ProgressMeter(std::string label, double t_end)
    : label_(std::move(label)), t_end_(t_end), terminal_(isatty(STDERR_FILENO) == 1),
      start_(Clock::now()), last_(start_) {
  enabled_ = g_mode == ProgressMode::On || (g_mode == ProgressMode::Auto && terminal_);
}

ProgressMeter::~ProgressMeter() {
  if (shown_ && terminal_) std::fprintf(stderr, "\r\033[K");
}

void ProgressMeter::operator()(double t) {
  if (!enabled_ || t <= 0) return;
  const Clock::time_point now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double since = std::chrono::duration<double>(now - last_).count();
  if (elapsed < kProgressAfterS || (shown_ && since < (terminal_ ? kTerminalRefreshS : kProgressLineS))) return;
  last_ = now;
  shown_ = true;
  const double eta = elapsed * (t_end_ - t) / t;
  std::fprintf(stderr, "%s%s: t = %.4g / %.4g s, elapsed %.1f s, ETA %.1f s%s", terminal_ ? "\r" : "", label_.c_str(), t,
               t_end_, elapsed, eta, terminal_ ? "\033[K" : "\n");
  std::fflush(stderr);
}

}  // namespace em
