#pragma once
/// A run's setting in every file eigenmass reads or writes: the key "dt" for
/// a fixed-step integrator, "tolerance" for an adaptive one (settingKindName),
/// chosen here once for writers and readers alike.
#include <nlohmann/json.hpp>
#include <string>

#include "solver/run_spec.hpp"
#include "solver/trajectory.hpp"

namespace em {

/// Writes s's setting under its key: j["dt"] = s.dt or j["tolerance"] = s.tol.
void putSetting(nlohmann::json& j, const RunSpec& s);

/// {"integrator": name, "dt" | "tolerance": setting}: how reports state a run.
nlohmann::json runSpecJson(const RunSpec& s);

/// The key `i`'s setting is read from in the object `v` at `path`; throws
/// InputError naming the other key if `v` holds it ("rk4 takes dt, not tolerance").
/// Whether the key itself is present is the caller's to check (a number or a list).
/// How a mechanism's run kept its loops closed (docs/report-format.md, "loops"):
/// the formulation and its options as run (ida: the DAE's own), the largest
/// violations, the rank and the projections; null for a run without loops.
nlohmann::json loopsJson(const RunEnd& r, const RunSpec& s);

std::string settingKeyIn(const nlohmann::json& v, const std::string& path, Integrator i);

}  // namespace em
