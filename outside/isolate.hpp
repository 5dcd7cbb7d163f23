#pragma once
/// Code from outside (a plugin's) run where it cannot take the harness down:
/// in a child process, its result sent back as text. A crash, a hang (no
/// beat for `timeout_s`) or an exception there is a failure the caller
/// reports, with the last time the work said it had reached.
#include <functional>
#include <string>

namespace em {

struct Isolated {
  bool ok = false;      ///< the work returned: `output` is what it returned
  std::string output;
  std::string failure;  ///< otherwise, one line: "crashed (SIGSEGV)", "no return within 10 s", the exception's text
  double t = 0;         ///< the last time the work beat with (isolatedBeat)
  bool beat = false;    ///< whether it ever beat
};

/// Run `work` in a child process and wait: the child returns its text, or
/// fails. A child that does not beat (isolatedBeat) for `timeout_s` is killed.
Isolated runIsolated(const std::function<std::string()>& work, double timeout_s);

/// In a child of runIsolated: the work is alive, at time t (two stores into a
/// shared page; nothing outside such a child).
void isolatedBeat(double t);

/// Default seconds a plugin's call may take before it counts as hung (--plugin-timeout).
constexpr double kPluginTimeout = 10.0;
/// How often the watch looks at a child (s): the shortest timeout it keeps.
constexpr double kPluginWatch = 0.1;
/// The longest timeout accepted (s): a day.
constexpr double kPluginTimeoutMax = 86400;

}  // namespace em
