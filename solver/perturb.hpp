#pragma once
/// A model's start displaced by seeded normal draws: the ensemble's members
/// (sweep/ensemble.hpp) and the Lyapunov exponent's nearby starts
/// (compare/lyapunov.hpp) are made by this one function, so both are
/// reproducible from (sigma, seed) alone.
#include <cstdint>

#include "solver/model.hpp"

namespace em {

/// `m` with every joint's q0 moved by sigma_q N(0, 1) per coordinate (a
/// quaternion turned by a rotation vector of such draws, kept unit) and u0 by
/// sigma_u N(0, 1), drawn body by body in file order from SplitMix64(seed)
/// by Box–Muller. Deterministic; sigma 0 leaves the start as it is.
Model perturbedStart(const Model& m, double sigma_q, double sigma_u, std::uint64_t seed);

}  // namespace em
