#pragma once
/// Joint limits as exact events (docs/theory.md §17): a coordinate reaching a
/// stop is located by root finding on the integrator's own step from the last
/// accepted state, Newton's impact law is applied there through A, and a
/// coordinate that comes to rest on its stop (e = 0, or a Zeno sequence of
/// impacts) is held there, a unilateral constraint, until its contact force
/// would pull. Depends on the formation only.
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "solver/model.hpp"
#include "solver/workspace.hpp"

namespace em {

/// One impact: when, which coordinate, its speed before and after, and the
/// kinetic energy the impact removed (J).
struct Impact {
  double t = 0;
  std::string coordinate;
  double u_before = 0, u_after = 0, energy_lost = 0;
  bool rests = false;  ///< it came to rest on the stop (held from here)
  /// An engine's soft or stabilized stop (reference/fixed_step.cpp): how far
  /// beyond the stop it let the coordinate go (rad or m) and for how long (s);
  /// 0 for an exact event. Its t is when the coordinate crossed the stop, its
  /// speeds those at the last step before and the first step after.
  double overshoot = 0, duration = 0;
};

/// A located crossing is put at its stop within this (s).
inline constexpr double kLimitTimeTol = 1e-12;
/// An approach slower than this (rad/s, m/s) ends a Zeno sequence: the
/// coordinate rests on its stop (a ball on a floor at e < 1 makes infinitely
/// many impacts in finite time; from 1 m/s at e = 0.5 the 21st is this slow).
inline constexpr double kRestSpeed = 1e-6;
/// Impacts kept in a trajectory (the count is kept beyond).
inline constexpr size_t kImpactsKept = 1000;

class JointLimitEvents {
 public:
  explicit JointLimitEvents(const Model& m);
  bool active() const { return !m_.limited.empty(); }

  /// How far coordinate c of y is inside its range (> 0 inside, < 0 beyond), at its nearer stop.
  double inside(const double* y, size_t c) const;
  /// The first free limited coordinate beyond its range in y, or -1.
  int beyond(const double* y) const;

  /// Put coordinate c on its stop and apply Newton's impact law there at time t
  /// (y's speeds change by the impulse through A); a slow approach or e = 0
  /// with the free acceleration into the stop holds it. Records the impact.
  void impact(double t, double* y, int c, const double* udot_free);
  /// While any coordinate is held: u' (dydt's speed part) with the held
  /// coordinates' accelerations zeroed through A (their contact forces), and
  /// their q' zeroed.
  void constrain(const double* y, double* dydt);
  /// After an accepted step: release a held coordinate whose contact force
  /// would pull (its free acceleration points away from the stop).
  void release(const double* y, const double* udot_free);
  bool anyHeld() const;

  double energyLost() const { return lost_; }
  const std::vector<Impact>& impacts() const { return impacts_; }
  long impactCount() const { return count_; }

 private:
  void formA(const double* y);
  double kinetic(const double* u) const;  // after formA
  const Model& m_;
  Workspace ws_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::VectorXd col_, u_;  // (nu)
  std::vector<int> held_;    // per limited coordinate: 0 free, -1 on its lower stop, +1 on its upper
  std::vector<int> held_u_;  // the held coordinates' speeds (reserved)
  Eigen::MatrixXd AinvE_, S_;
  Eigen::VectorXd r_;
  std::vector<Impact> impacts_;
  long count_ = 0;
  double lost_ = 0;
};

}  // namespace em
