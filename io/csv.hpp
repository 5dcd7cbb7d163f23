#pragma once
/// Trajectory CSV (README, "Trajectory CSV columns"): t, coordinates, speeds,
/// energy, kinetic, every body's pose, then the eigenfactor diagnostics if any.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "solver/trajectory.hpp"

namespace em {

/// The declared columns of the trajectory CSV, shared by its writer and by
/// the reader of recorded runs (outside/recorded.cpp): a body's pose is
/// "<body>.<column>"; the energies follow the speeds; the eigenfactor
/// diagnostics close the row where a method has them.
inline constexpr std::array<const char*, 7> kPoseColumns = {"x", "y", "z", "qw", "qx", "qy", "qz"};
inline constexpr std::array<const char*, 3> kEnergyColumns = {"energy", "kinetic", "dissipated"};
inline constexpr std::array<const char*, 5> kDiagnosticColumns = {"orth_err", "offdiag_rel", "min_gap", "max_Omega", "inv_err"};
/// A mechanism's columns (Trajectory::loop_samples), then its lambda.<loop>.<row> ones.
inline constexpr std::array<const char*, 4> kLoopColumns = {"loops.position_m", "loops.position_rad", "loops.velocity_m_per_s",
                                                           "loops.velocity_rad_per_s"};

/// Most lines a CSV file read from outside may have (with the 256 MiB bound on
/// its bytes, io/json_input.hpp): what is read stays within ~1 GiB.
inline constexpr size_t kMaxCsvLines = 10'000'000;

/// A CSV file read from outside, bounded: its bytes (for its digest) and its
/// lines, a CR before each newline dropped.
struct CsvText {
  std::string bytes;
  std::vector<std::string> lines;
};
/// Read `path` (a `what`) within the bounds: a folder, a device or a pipe, an
/// unreadable file, more than 256 MiB or more than kMaxCsvLines lines throws
/// one line naming it.
CsvText readCsvText(const std::string& path, const std::string& what);
/// A table's column: its header name and how a row gives its cell. A CSV
/// written from a list of these cannot have its header and its cells apart.
template <class Row>
struct CsvColumn {
  const char* name;
  std::function<std::string(const Row&)> cell;
};
/// The header line, then one line per row.
template <class Row>
std::string csvTable(const std::vector<CsvColumn<Row>>& columns, const std::vector<Row>& rows) {
  std::string o;
  for (size_t c = 0; c < columns.size(); ++c) (o += c ? "," : "") += columns[c].name;
  o += '\n';
  for (const Row& r : rows) {
    for (size_t c = 0; c < columns.size(); ++c) (o += c ? "," : "") += columns[c].cell(r);
    o += '\n';
  }
  return o;
}

/// One line's comma-separated fields, blanks around each trimmed.
std::vector<std::string> splitCsvFields(const std::string& line);

/// The CSV column names, in order.
std::vector<std::string> csvColumns(const Trajectory& tr);

/// Write `tr` to a temporary beside `path`, then rename: an interrupted run leaves no half file.
void writeCsv(const Trajectory& tr, const std::string& path);

}  // namespace em
