#include "io/csv.hpp"

#include <algorithm>

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "io/json_input.hpp"

namespace em {

namespace {

void writeRow(std::ostream& out, const Trajectory& tr, size_t k) {
  out << tr.t[k];
  for (int i = 0; i < tr.q[k].size(); ++i) out << ',' << tr.q[k][i];
  for (int i = 0; i < tr.u[k].size(); ++i) out << ',' << tr.u[k][i];
  out << ',' << tr.energy[k] << ',' << tr.kinetic[k] << ',' << tr.dissipated[k];
  for (const Pose& p : tr.poses[k])
    out << ',' << p.p.x() << ',' << p.p.y() << ',' << p.p.z() << ',' << p.quat[0] << ',' << p.quat[1] << ','
        << p.quat[2] << ',' << p.quat[3];
  if (!tr.diag.empty()) {
    const SampleDiagnostics& d = tr.diag[k];
    out << ',' << d.orth_err << ',' << d.offdiag_rel << ',' << d.min_gap << ',' << d.max_Omega << ',' << d.inv_err;
  }
  if (!tr.loop_samples.empty()) {
    const LoopSample& l = tr.loop_samples[k];
    out << ',' << l.position_m << ',' << l.position_rad << ',' << l.velocity_m << ',' << l.velocity_rad;
    for (int i = 0; i < l.lambda.size(); ++i) out << ',' << l.lambda[i];
  }
  out << '\n';
}
}  // namespace

std::vector<std::string> csvColumns(const Trajectory& tr) {
  std::vector<std::string> c = {"t"};
  c.insert(c.end(), tr.q_names.begin(), tr.q_names.end());
  c.insert(c.end(), tr.u_names.begin(), tr.u_names.end());
  c.insert(c.end(), kEnergyColumns.begin(), kEnergyColumns.end());
  for (const auto& b : tr.body_names)
    for (const char* col : kPoseColumns) c.push_back(b + "." + col);
  if (!tr.diag.empty()) c.insert(c.end(), kDiagnosticColumns.begin(), kDiagnosticColumns.end());
  if (!tr.loop_samples.empty()) {
    c.insert(c.end(), kLoopColumns.begin(), kLoopColumns.end());
    c.insert(c.end(), tr.lambda_names.begin(), tr.lambda_names.end());
  }
  return c;
}

void writeCsv(const Trajectory& tr, const std::string& path) {
  writeAtomic(path, "trajectory", [&tr](std::ostream& out) {
    out.precision(17);
    const std::vector<std::string> cols = csvColumns(tr);
    for (size_t i = 0; i < cols.size(); ++i) out << (i ? "," : "") << cols[i];
    out << '\n';
    for (size_t k = 0; k < tr.size(); ++k) writeRow(out, tr, k);
  });
}

CsvText readCsvText(const std::string& path, const std::string& what) {
  CsvText t;
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) && !std::filesystem::is_directory(status))
    throw std::runtime_error(path + ": not a regular file (a device or a pipe has no bound): not a " + what);
  t.bytes = readFile(path, what);  // refuses a folder, and stops past 256 MiB (/dev/zero included)
  // The encoding: UTF-8 (ASCII) text. A UTF-8 byte-order mark (spreadsheets write one) is skipped;
  // UTF-16 and any other NUL-bearing file is refused, named, rather than misread byte by byte.
  const bool bom = t.bytes.rfind("\xEF\xBB\xBF", 0) == 0;
  if (t.bytes.rfind("\xFF\xFE", 0) == 0 || t.bytes.rfind("\xFE\xFF", 0) == 0)
    throw std::runtime_error(path + ": UTF-16 text (it starts with a UTF-16 byte-order mark): save it as UTF-8 for a " + what);
  if (const size_t nul = t.bytes.find('\0'); nul != std::string::npos)
    throw std::runtime_error(path + ": a NUL byte at line " + std::to_string(1 + std::count(t.bytes.begin(), t.bytes.begin() + nul, '\n')) +
                             " (UTF-16 or binary, not text): not a " + what);
  std::istringstream ls(bom ? t.bytes.substr(3) : t.bytes);
  for (std::string l; std::getline(ls, l);) {
    if (t.lines.size() == kMaxCsvLines)
      throw std::runtime_error(path + ": more than " + std::to_string(kMaxCsvLines) + " lines: not a " + what);
    if (!l.empty() && l.back() == '\r') l.pop_back();
    t.lines.push_back(std::move(l));
  }
  return t;
}

std::vector<std::string> splitCsvFields(const std::string& line) {
  std::vector<std::string> f;
  std::string cur;
  std::istringstream s(line);
  while (std::getline(s, cur, ',')) {
    const size_t a = cur.find_first_not_of(" \t"), b = cur.find_last_not_of(" \t");
    f.push_back(a == std::string::npos ? "" : cur.substr(a, b - a + 1));
  }
  if (!line.empty() && line.back() == ',') f.emplace_back();
  return f;
}

}  // namespace em
