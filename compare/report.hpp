#pragma once
/// The JSON report `eigenmass-report/1` (docs/report-format.md), written atomically.
#include <cmath>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "compare/comparison.hpp"

namespace em {

/// NaN and Inf are not JSON: every output writes a non-finite number as null,
/// and an absent one as null; readers of results turn null back.
inline nlohmann::json finiteOrNull(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }
inline nlohmann::json orNull(const std::optional<double>& x) { return x ? nlohmann::json(*x) : nlohmann::json(nullptr); }
inline std::optional<double> optionalFrom(const nlohmann::json& j) {
  return j.is_null() ? std::nullopt : std::optional<double>(j.get<double>());
}
inline double numberFrom(const nlohmann::json& j) { return j.is_null() ? NAN : j.get<double>(); }

/// A threshold as a report key: shortest exact scientific form, '.' written
/// as 'p' so the key has no dot ("1e-3", "2p5e-3"; docs/report-format.md).
std::string thresholdKey(double th);

/// The report of a comparison; `gate` is null when no gate was asked for.
/// `max_series_points` bounds the decimated plotting series.
nlohmann::json makeReport(const ComparisonResult& r, const nlohmann::json& gate = nullptr, int max_series_points = 1000);

/// A failure as every output writes it: {t, kind (the registry's failure
/// name), cause, cond_A (null unless known)}; of a method, null when it completed.
nlohmann::json failureJson(const std::optional<double>& t, Failure kind, const std::string& cause, double cond_A);
nlohmann::json failureJson(const MethodMetrics& m);

/// Write JSON to a temporary file beside `path`, then rename: a reader never
/// sees a half-written report, and an interrupted run leaves none.
void writeJsonAtomic(const nlohmann::json& j, const std::string& path);

}  // namespace em
