#pragma once
/// Text of numbers in messages, tables and keys: one formatter for the whole project.
#include <string>

namespace em {

/// "%g" with `digits` significant digits: "0.001", "1e-10", "2.5e-13" (never
/// "0.000000" for a tiny number, as std::to_string gives).
std::string gnum(double x, int digits = 6);

}  // namespace em
