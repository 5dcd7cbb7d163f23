#include "solver/text.hpp"

#include <cstdio>

namespace em {

std::string gnum(double x, int digits) {
  char b[40];
  std::snprintf(b, sizeof b, "%.*g", digits, x);
  return b;
}

}  // namespace em
