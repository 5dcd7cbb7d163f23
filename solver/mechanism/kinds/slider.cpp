// The slider closure (docs/theory.md §15): b's point stays on the line through
// a's point along axis_a (with a), and b's frame at the turn relative to a's it
// has at the start (Loop::rel): a prismatic joint as a closure, 5 rows.
#include "solver/mechanism/loop_rows.hpp"

namespace em {

namespace {
double form(const LoopContext& x, int r, LoopState& ls) {
  lineRows(x, r, ls);
  return frameRows(x, relativeTurn(x, ls), r + 2, ls);
}
}  // namespace

const LoopEquations kSliderLoop = {form, lineGap};

}  // namespace em
