#include "solver/trajectory.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace em {

Trajectory makeTrajectory(const Model& m, const std::string& method, const std::string& integrator) {
  Trajectory tr;
  tr.scene = m.name;
  tr.method = method;
  tr.integrator = integrator;
  tr.q_names = m.qNames();
  tr.u_names = m.uNames();
  tr.body_names.resize(m.n());
  for (const Body& b : m.bodies) tr.body_names[b.file_index] = b.name;
  return tr;
}

namespace {
const char* kPoseCols[] = {"x", "y", "z", "qw", "qx", "qy", "qz"};
const char* kDiagCols[] = {"orth_err", "offdiag_rel", "min_gap", "max_Omega", "inv_err"};
}  // namespace

void writeCsv(const Trajectory& tr, const std::string& path) {
  // Written to a temporary and renamed: an interrupted run leaves no half file.
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error(path + ": cannot write");
    out.precision(17);
    out << "t";
    for (auto& n : tr.q_names) out << ',' << n;
    for (auto& n : tr.u_names) out << ',' << n;
    out << ",energy,kinetic";
    for (auto& b : tr.body_names)
      for (auto* c : kPoseCols) out << ',' << b << '.' << c;
    if (!tr.diag.empty())
      for (auto* c : kDiagCols) out << ',' << c;
    out << '\n';
    for (size_t k = 0; k < tr.size(); ++k) {
      out << tr.t[k];
      for (int i = 0; i < tr.q[k].size(); ++i) out << ',' << tr.q[k][i];
      for (int i = 0; i < tr.u[k].size(); ++i) out << ',' << tr.u[k][i];
      out << ',' << tr.energy[k] << ',' << tr.kinetic[k];
      for (const Pose& p : tr.poses[k])
        out << ',' << p.p.x() << ',' << p.p.y() << ',' << p.p.z() << ',' << p.quat[0] << ',' << p.quat[1] << ','
            << p.quat[2] << ',' << p.quat[3];
      if (!tr.diag.empty()) {
        const SampleDiagnostics& d = tr.diag[k];
        out << ',' << d.orth_err << ',' << d.offdiag_rel << ',' << d.min_gap << ',' << d.max_Omega << ',' << d.inv_err;
      }
      out << '\n';
    }
    if (!out) throw std::runtime_error(path + ": write failed");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error(path + ": cannot rename the temporary file");
}

Trajectory readCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> cols;
  {
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cols.push_back(c);
  }
  Trajectory tr;
  size_t k = 1;
  for (; k < cols.size() && cols[k].find(".q") != std::string::npos && cols[k].find(".qw") == std::string::npos; ++k)
    tr.q_names.push_back(cols[k]);
  for (; k < cols.size() && cols[k].find(".u") != std::string::npos; ++k) tr.u_names.push_back(cols[k]);
  const size_t e = k;
  if (e + 1 >= cols.size() || cols[e] != "energy" || cols[e + 1] != "kinetic")
    throw std::runtime_error(path + ": not an eigenmass trajectory CSV");
  const size_t p0 = e + 2;  // first pose column
  size_t pose_cols = 0;     // diagnostics columns, if any, have no "body." prefix
  while (p0 + pose_cols < cols.size() && cols[p0 + pose_cols].find('.') != std::string::npos) ++pose_cols;
  const size_t nb = pose_cols / 7;
  for (size_t b = 0; b < nb; ++b) tr.body_names.push_back(cols[p0 + 7 * b].substr(0, cols[p0 + 7 * b].size() - 2));
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) v.push_back(std::stod(c));
    tr.t.push_back(v[0]);
    tr.q.push_back(Eigen::Map<Eigen::VectorXd>(v.data() + 1, tr.q_names.size()));
    tr.u.push_back(Eigen::Map<Eigen::VectorXd>(v.data() + 1 + tr.q_names.size(), tr.u_names.size()));
    tr.energy.push_back(v[e]);
    tr.kinetic.push_back(v[e + 1]);
    std::vector<Pose> poses(nb);
    for (size_t b = 0; b < nb; ++b) {
      const double* p = v.data() + p0 + 7 * b;
      poses[b].p = Vec3(p[0], p[1], p[2]);
      poses[b].quat = Vec4(p[3], p[4], p[5], p[6]);
    }
    tr.poses.push_back(poses);
  }
  return tr;
}

}  // namespace em
