// The universal closure (docs/theory.md §15): the points meet and axis_a
// (with a) stays square to axis_b (with b), 4 rows; its turn is the axes'
// departure from square.
#include <cmath>

#include "solver/mechanism/loop_rows.hpp"

namespace em {

namespace {
double form(const LoopContext& x, int r, LoopState& ls) {
  pointRows(x, r, ls);
  const Loop& l = x.loop;
  const Vec3 e = rotationOf(x.ws, l.a.body) * l.axis_a, f = rotationOf(x.ws, l.b.body) * l.axis_b;
  pairRow(relativeTurn(x, ls), e, f, r + 3, ls);
  return std::atan2(std::abs(e.dot(f)), e.cross(f).norm());
}
}  // namespace

const LoopEquations kUniversalLoop = {form, pointGap};

}  // namespace em
