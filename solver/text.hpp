#pragma once
/// Text of numbers in messages, tables and keys: one formatter for the whole project.
#include <csignal>
#include <string>
#include <utility>

namespace em {

/// "%g" with `digits` significant digits: "0.001", "1e-10", "2.5e-13" (never
/// "0.000000" for a tiny number, as std::to_string gives).
std::string gnum(double x, int digits = 6);

/// x and its bound, each with the fewest digits (from `digits` up to 17) that
/// tell them apart: "1.0000001 beyond 1", "1000001 samples, more than the
/// budget of 1000000", never "1 beyond 1". Equal numbers keep `digits`.
std::pair<std::string, std::string> gnumApart(double x, double bound, int digits = 6);

/// The process's own stderr while an engine's messages are gathered
/// (reference/engine_messages.hpp points file descriptor 2 at a temporary file
/// meanwhile): the interrupt handler's last line goes here, never into that
/// file. 2 otherwise; async-signal-safe to read.
extern volatile std::sig_atomic_t g_stderr_fd;

}  // namespace em
