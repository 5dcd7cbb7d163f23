#pragma once
/// MuJoCo as a trajectory engine (method `mujoco`): the same Model as MJCF
/// (reference/mujoco_system.hpp), stepped by MuJoCo's own fixed-step
/// integrators (euler, rk4, implicit) and sampled through the shared sampler.
#include "solver/model.hpp"
#include "solver/run_spec.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// Integrate `m` from its initial state as `spec` says (method mujoco, a
/// MuJoCo integrator, fixed step spec.dt), sampled every spec.output_dt. A
/// MuJoCo warning (a bad qacc, a non-finite state) ends the run with its time
/// and cause; bad settings throw.
Trajectory simulateMujoco(const Model& m, const CheckedRunSpec& spec, const SampleObserver& observe = {});

}  // namespace em
