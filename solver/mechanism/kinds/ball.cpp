// The ball closure (docs/theory.md §15): a's point meets b's, 3 rows (eqs. (M1)-(M3)).
#include "solver/mechanism/loop_rows.hpp"

namespace em {

namespace {
double form(const LoopContext& x, int r, LoopState& ls) {
  pointRows(x, r, ls);
  return 0;
}
}  // namespace

const LoopEquations kBallLoop = {form, pointGap};

}  // namespace em
