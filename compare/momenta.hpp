#pragma once
/// Momentum drift of a free system over a run (Erez, Tassa and Todorov's
/// conservation test; docs/engines.md): with every root on a free joint
/// without a spring, only gravity acts from outside, so p(t) - M g t and the
/// angular momentum about the CM, H_c, are constants of the motion.
#include <optional>

#include "solver/model.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// Largest drift over the samples, relative to the size at t = 0: |p(t) - M g t - p(0)| / |p(0)|
/// and |H_c(t) - H_c(0)| / |H_c(0)|; none where that size is 0 (a system at rest has no scale).
struct MomentumDrift {
  std::optional<double> p, H;
};

/// Whether `m` is free: every root body on a free joint without a spring.
bool freeSystem(const Model& m);

/// The drift of `tr` (a run of `m`); none for a system that is not free.
std::optional<MomentumDrift> momentumDrift(const Model& m, const Trajectory& tr);

}  // namespace em
