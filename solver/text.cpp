#include "solver/text.hpp"

#include <cstdio>

namespace em {

std::string gnum(double x, int digits) {
  char b[40];
  std::snprintf(b, sizeof b, "%.*g", digits, x);
  return b;
}

std::pair<std::string, std::string> gnumApart(double x, double bound, int digits) {
  for (int d = digits; d < 17 && x != bound; ++d)
    if (gnum(x, d) != gnum(bound, d)) return {gnum(x, d), gnum(bound, d)};
  return {gnum(x, x != bound ? 17 : digits), gnum(bound, x != bound ? 17 : digits)};
}

volatile std::sig_atomic_t g_stderr_fd = 2;

}  // namespace em
