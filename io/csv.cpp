#include "io/csv.hpp"

#include "io/atomic_file.hpp"

namespace em {

namespace {
const char* kPoseCols[] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
const char* kDiagCols[] = {"orth_err", "offdiag_rel", "min_gap", "max_Omega", "inv_err"};

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
  out << '\n';
}
}  // namespace

std::vector<std::string> csvColumns(const Trajectory& tr) {
  std::vector<std::string> c = {"t"};
  c.insert(c.end(), tr.q_names.begin(), tr.q_names.end());
  c.insert(c.end(), tr.u_names.begin(), tr.u_names.end());
  c.push_back("energy");
  c.push_back("kinetic");
  c.push_back("dissipated");
  for (const auto& b : tr.body_names)
    for (const char* col : kPoseCols) c.push_back(b + "." + col);
  if (!tr.diag.empty())
    for (const char* col : kDiagCols) c.push_back(col);
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

}  // namespace em
