#pragma once
/// The rows closure kinds are made of (docs/theory.md §15): a point meeting a
/// point (eqs. (M1)-(M3)), a point on a line, a direction square to another
/// (eq. (M4)), a frame held at a relative turn, and the angles that measure a
/// kind's turn (eq. (M4b)). A kind (solver/mechanism/kinds/) is a few of these.
#include "solver/mechanism/loops.hpp"
#include "solver/point_kinematics.hpp"

namespace em {

/// Rows r..r+2: a's point meets b's, g = x_a - x_b (eqs. (M1)-(M3)).
void pointRows(const LoopContext& x, int r, LoopState& ls);
/// Rows r, r+1: b's point stays on the line through a's point along axis_a
/// (turning with a): g_k = t_k . (x_b - x_a) for t_1, t_2 square to the axis.
void lineRows(const LoopContext& x, int r, LoopState& ls);

/// The relative turn of a loop's bodies: J_w,a - J_w,b into ls.Jw, and
/// omega_a, omega_b and alpha_a - alpha_b at u' = 0, shared by its direction rows.
struct RelativeTurn {
  Vec3 wa, wb, alpha;
  const std::vector<int>* speeds;  ///< the loop's (Model::loop_speeds): ls.Jw's only nonzero columns
};
RelativeTurn relativeTurn(const LoopContext& x, LoopState& ls);
/// Row r: unit e (turning with a) stays square to unit f (turning with b):
/// g = e . f, G = (e x f)^T (J_w,a - J_w,b) (eq. (M4)).
void pairRow(const RelativeTurn& turn, const Vec3& e, const Vec3& f, int r, LoopState& ls);
/// Rows r..r+2: b's frame stays at R_a rel (Loop::rel); returns the angle of
/// (R_a rel)^T R_b (eq. (M4b)).
double frameRows(const LoopContext& x, const RelativeTurn& turn, int r, LoopState& ls);

/// The gaps of those rows from world points: |xb - xa| where the points
/// meet; xb's distance from the line through xa along R_a axis_a.
double pointGap(const Loop& l, const Vec3& xa, const Vec3& xb, const Mat3& Ra);
double lineGap(const Loop& l, const Vec3& xa, const Vec3& xb, const Mat3& Ra);

/// Two unit vectors perpendicular to unit n, fixed by n alone.
void perpendicularPair(const Vec3& n, Vec3& t1, Vec3& t2);
/// The angle between unit vectors e and f, accurate near 0 (theory.md eq. (M4b)).
double angleBetween(const Vec3& e, const Vec3& f);

}  // namespace em
