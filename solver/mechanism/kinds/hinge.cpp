// The hinge closure (docs/theory.md §15): the points meet and axis_a (with a)
// stays along axis_b (with b): square to two perpendiculars of axis_b, 5 rows.
#include "solver/mechanism/loop_rows.hpp"

namespace em {

namespace {
double form(const LoopContext& x, int r, LoopState& ls) {
  pointRows(x, r, ls);
  const Loop& l = x.loop;
  const Mat3 Ra = rotationOf(x.ws, l.a.body), Rb = rotationOf(x.ws, l.b.body);
  const RelativeTurn turn = relativeTurn(x, ls);
  Vec3 t1, t2;
  perpendicularPair(l.axis_b, t1, t2);
  const Vec3 e = Ra * l.axis_a;
  pairRow(turn, e, Rb * t1, r + 3, ls);
  pairRow(turn, e, Rb * t2, r + 4, ls);
  return angleBetween(e, Rb * l.axis_b);
}
}  // namespace

const LoopEquations kHingeLoop = {form, pointGap};

}  // namespace em
