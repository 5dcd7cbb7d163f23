#pragma once
/// Progress of a long run on stderr: which run, simulated time / t_end,
/// elapsed wall time and the time left. Shown for runs that last longer than
/// kProgressAfterS; by default only when stderr is a terminal (`--progress`
/// forces it, one line every kProgressLineS; `--no-progress` silences it and
/// the commands' "running ..." lines).
#include <chrono>
#include <string>

namespace em {

enum class ProgressMode { Auto, On, Off };
/// Set once by the CLI before any run.
void setProgressMode(ProgressMode mode);
/// The mode set (Off: `--no-progress`, no "running ..." lines either).
ProgressMode progressMode();

constexpr double kProgressAfterS = 2.0;  ///< a run shorter than this shows nothing
constexpr double kProgressLineS = 10.0;  ///< interval of the lines when stderr is not a terminal

/// One run's meter; its call operator takes the time of each output sample.
class ProgressMeter {
 public:
  ProgressMeter(std::string label, double t_end);
  ~ProgressMeter();  ///< clears a terminal's progress line
  ProgressMeter(const ProgressMeter&) = delete;
  ProgressMeter& operator=(const ProgressMeter&) = delete;
  void operator()(double t);

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  double t_end_;
  bool enabled_, terminal_;
  bool shown_ = false;
  Clock::time_point start_, last_;
};

}  // namespace em
