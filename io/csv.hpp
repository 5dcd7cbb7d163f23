#pragma once
/// Trajectory CSV (README, "Trajectory CSV columns"): t, coordinates, speeds,
/// energy, kinetic, every body's pose, then the eigenfactor diagnostics if any.
#include <string>

#include "solver/trajectory.hpp"

namespace em {

/// The CSV column names, in order.
std::vector<std::string> csvColumns(const Trajectory& tr);

/// Write `tr` to a temporary beside `path`, then rename: an interrupted run leaves no half file.
void writeCsv(const Trajectory& tr, const std::string& path);

}  // namespace em
