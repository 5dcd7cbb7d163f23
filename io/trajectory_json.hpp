#pragma once
/// A trajectory as JSON and back, bit for bit (doubles round-trip): how a
/// sweep keeps a scene's reference run for the cases run elsewhere
/// (docs/sweep.md). The RunSpec is the reader's: it knows what made the run.
#include <string>

#include <nlohmann/json.hpp>

#include "solver/trajectory.hpp"

namespace em {

/// Samples (t, q, u, energies, poses), names, status, failure and cost.
/// Eigenfactor diagnostics are not kept.
nlohmann::json trajectoryJson(const Trajectory& tr);

/// The trajectory `trajectoryJson` wrote, made by `run`. Throws
/// std::runtime_error naming `source` for a file that is not one.
Trajectory trajectoryFromJson(const nlohmann::json& j, const RunSpec& run, const std::string& source);

}  // namespace em
