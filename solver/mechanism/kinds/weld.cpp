// The weld closure (docs/theory.md §15): the points meet and b's frame stays
// at the turn relative to a's it has at the start (Loop::rel), 6 rows.
#include "solver/mechanism/loop_rows.hpp"

namespace em {

namespace {
double form(const LoopContext& x, int r, LoopState& ls) {
  pointRows(x, r, ls);
  return frameRows(x, relativeTurn(x, ls), r + 3, ls);
}
}  // namespace

const LoopEquations kWeldLoop = {form, pointGap};

}  // namespace em
