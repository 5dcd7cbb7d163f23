#include "outside/recorded.hpp"
#include "solver/control.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/csv.hpp"
#include "io/digest.hpp"
#include "io/json_input.hpp"
#include "io/scene_json.hpp"
#include "solver/applied_forces.hpp"
#include "solver/formation.hpp"
#include "solver/mechanism/loops.hpp"
#include "solver/joint.hpp"
#include "solver/text.hpp"

namespace em {

namespace {

// Columns eigenmass's own CSV has beside t, q, u and poses (io/csv.hpp): read past, recomputed.
bool ownColumn(const std::string& c) {
  return std::find(kEnergyColumns.begin(), kEnergyColumns.end(), c) != kEnergyColumns.end() ||
         std::find(kDiagnosticColumns.begin(), kDiagnosticColumns.end(), c) != kDiagnosticColumns.end() ||
         std::find(kLoopColumns.begin(), kLoopColumns.end(), c) != kLoopColumns.end() || c.rfind("lambda.", 0) == 0;
}

struct Entry {
  RecordedRun run;
  std::string grid;  // how the last grid was met
  Method id;
};

std::deque<Entry>& entries() {
  static std::deque<Entry> table;
  return table;
}

Entry* findEntry(Method id) {
  for (Entry& e : entries())
    if (e.id == id) return &e;
  return nullptr;
}

// One line of a defect: "file: line L, column C ('name'): what".
struct Where {
  const std::string& file;
  std::invalid_argument at(long line, const std::string& what) const {
    return std::invalid_argument(file + ": line " + std::to_string(line) + ": " + what);
  }
  std::invalid_argument at(long line, size_t col, const std::string& name, const std::string& what) const {
    return std::invalid_argument(file + ": line " + std::to_string(line) + ", column " + std::to_string(col + 1) + " ('" +
                                 printable(name, 40) + "'): " + what);
  }
};

// The columns of the header, checked against the scene: their index by name.
struct Header {
  std::map<std::string, size_t> col;
  size_t size = 0;
  bool has(const std::string& n) const { return col.count(n) != 0; }
};

// Every column name eigenmass knows for this scene, and the prefixes (bodies, joints) it knows.
bool knownColumn(const Model& m, const std::string& c, const std::vector<std::string>& qn, const std::vector<std::string>& un) {
  if (std::find(qn.begin(), qn.end(), c) != qn.end() || std::find(un.begin(), un.end(), c) != un.end()) return true;
  if (ownColumn(c)) return true;
  for (const Body& b : m.bodies)
    for (const char* p : kPoseColumns)
      if (c == b.name + "." + p) return true;
  return false;
}

Header readHeader(const Where& w, const Model& m, const std::string& line, long lineno) {
  const std::vector<std::string> names = splitCsvFields(line);
  if (names.empty() || names[0] != "t") throw w.at(lineno, "the header's first column must be 't' (got '" + (names.empty() ? "" : printable(names[0], 40)) + "')");
  const std::vector<std::string> qn = m.qNames(), un = m.uNames();
  Header h;
  h.size = names.size();
  for (size_t c = 0; c < names.size(); ++c) {
    if (names[c].empty()) throw w.at(lineno, c, "", "an empty column name");
    if (h.has(names[c])) throw w.at(lineno, c, names[c], "named twice (also column " + std::to_string(h.col[names[c]] + 1) + ")");
    if (c > 0 && !knownColumn(m, names[c], qn, un)) {
      const std::string prefix = names[c].substr(0, names[c].find('.'));
      throw w.at(lineno, c, names[c], names[c].find('.') != std::string::npos
                                          ? "scene '" + m.name + "' has no body or joint '" + printable(prefix, 40) + "' (a file of another scene?)"
                                          : "not a column of the joint-coordinate or body-pose format (docs/report-format.md)");
    }
    h.col[names[c]] = c;
  }
  return h;
}

// The first of `names` the header lacks, or "".
std::string firstMissing(const Header& h, const std::vector<std::string>& names) {
  for (const std::string& n : names)
    if (!h.has(n)) return n;
  return "";
}

std::vector<std::string> poseColumns(const Model& m) {
  std::vector<std::string> c;
  for (const Body& b : m.bodies)
    for (const char* p : kPoseColumns) c.push_back(b.name + "." + p);
  return c;
}

// Which format the header is, refusing one that is neither or half of one.
std::string formatOf(const Where& w, const Model& m, const Header& h, long lineno, bool& with_u) {
  const std::vector<std::string> qn = m.qNames(), un = m.uNames();
  const bool any_q = std::any_of(qn.begin(), qn.end(), [&](const std::string& n) { return h.has(n); });
  const std::vector<std::string> pc = poseColumns(m);
  const bool any_pose = std::any_of(pc.begin(), pc.end(), [&](const std::string& n) { return h.has(n); });
  if (any_q) {
    if (const std::string miss = firstMissing(h, qn); !miss.empty())
      throw w.at(lineno, "column '" + miss + "' is missing (joint-coordinate format: t, then every coordinate of the scene)");
    const bool any_u = std::any_of(un.begin(), un.end(), [&](const std::string& n) { return h.has(n); });
    if (const std::string miss = firstMissing(h, un); any_u && !miss.empty())
      throw w.at(lineno, "column '" + miss + "' is missing (the speeds are all given or none)");
    with_u = any_u;
    return "joint-coordinates";
  }
  if (!any_pose) throw w.at(lineno, "neither format: no coordinate column (e.g. '" + qn[0] + "') and no pose column (e.g. '" + pc[0] + "')");
  if (const std::string miss = firstMissing(h, pc); !miss.empty())
    throw w.at(lineno, "column '" + miss + "' is missing (body-pose format: t, then every body's x, y, z, qw, qx, qy, qz)");
  with_u = false;
  return "body-poses";
}

// The data rows as numbers, checked: field count, numbers, finite, time increasing from 0.
std::vector<std::vector<double>> readRows(const Where& w, const std::vector<std::string>& lines, size_t first, const Header& h,
                                          std::vector<long>& lineno) {
  std::vector<std::string> names(h.size);
  for (const auto& [n, c] : h.col) names[c] = n;
  std::vector<std::vector<double>> rows;
  for (size_t k = first; k < lines.size(); ++k) {
    const long L = static_cast<long>(k) + 1;
    if (lines[k].empty()) continue;
    const std::vector<std::string> f = splitCsvFields(lines[k]);
    if (f.size() != h.size) throw w.at(L, std::to_string(f.size()) + " fields, the header has " + std::to_string(h.size));
    std::vector<double> row(h.size);
    for (size_t c = 0; c < f.size(); ++c) {
      if (f[c].empty()) throw w.at(L, c, names[c], "empty");
      char* end = nullptr;
      row[c] = std::strtod(f[c].c_str(), &end);
      if (*end != '\0') throw w.at(L, c, names[c], "not a number: '" + printable(f[c], 40) + "'");
      if (f[c].find_first_of("xX") != std::string::npos)  // strtod reads C99's hexadecimal floats; no CSV writer does
        throw w.at(L, c, names[c], "a hexadecimal number '" + printable(f[c], 40) + "': decimal numbers only");
      if (!std::isfinite(row[c])) throw w.at(L, c, names[c], "not finite: '" + printable(f[c], 40) + "'");
    }
    if (rows.empty() && std::abs(row[0]) > 1e-12) throw w.at(L, 0, "t", "the first sample is at t = " + gnum(row[0]) + "; the scene starts at 0");
    if (!rows.empty() && !(row[0] > rows.back()[0]))
      throw w.at(L, 0, "t", "time " + gnum(row[0], 17) + " does not increase (line " + std::to_string(lineno.back()) + " has " + gnum(rows.back()[0], 17) + ")");
    rows.push_back(std::move(row));
    lineno.push_back(L);
  }
  if (rows.size() < 2) throw std::invalid_argument(w.file + ": fewer than two samples");
  return rows;
}

// "# key: value" lines before the header.
size_t readDeclared(const Where& w, const std::vector<std::string>& lines, RecordedRun& r) {
  size_t k = 0;
  for (; k < lines.size() && (lines[k].empty() || lines[k][0] == '#'); ++k) {
    const std::string l = lines[k].empty() ? "" : lines[k].substr(1);
    const size_t colon = l.find(':');
    if (l.find_first_not_of(" \t") == std::string::npos) continue;
    if (colon == std::string::npos) {
      r.declared["note"] += (r.declared["note"].empty() ? "" : " ") + l.substr(l.find_first_not_of(" \t"));
      continue;
    }
    const auto trim = [](std::string s) {
      const size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
      return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
    };
    const std::string key = trim(l.substr(0, colon)), value = trim(l.substr(colon + 1));
    if (r.declared.count(key))  // the last would win, silently
      throw w.at(static_cast<long>(k) + 1, "'" + printable(key, 40) + "' declared twice (a '# key: value' line is said once)");
    r.declared[key] = value;
    if (key == "cpu_s") {
      char* end = nullptr;
      r.cpu_s = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || !std::isfinite(r.cpu_s) || r.cpu_s < 0)
        throw w.at(static_cast<long>(k) + 1, "cpu_s: a CPU time in seconds >= 0, got '" + printable(value, 40) + "'");
    }
  }
  if (k == lines.size()) throw std::invalid_argument(w.file + ": no header line (t, then the columns; docs/report-format.md)");
  return k;
}

}  // namespace

namespace {

// The scene's initial state, met by the first sample within kRecordedStartTol.
void checkStart(const Where& w, const Model& m, long line, const Eigen::VectorXd& q, const Eigen::VectorXd* u) {
  const Eigen::VectorXd q0 = m.q0(), u0 = m.u0();
  const std::vector<std::string> qn = m.qNames(), un = m.uNames();
  const std::vector<int> pq = m.qFilePermutation(), pu = m.uFilePermutation();
  Eigen::VectorXd d = q - q0;
  for (const Body& b : m.bodies)  // q and -q are one rotation
    if (const int k = jointQuat(b.joint.type); k >= 0) {
      const auto a = q.segment<4>(b.iq + k), z = q0.segment<4>(b.iq + k);
      d.segment<4>(b.iq + k) = (a - z).norm() <= (a + z).norm() ? Eigen::Vector4d(a - z) : Eigen::Vector4d(a + z);
    }
  for (size_t k = 0; k < qn.size(); ++k)
    if (std::abs(d[pq[k]]) > kRecordedStartTol)
      throw w.at(line, "the first sample is not the scene's initial state: '" + qn[k] + "' is " + gnum(q[pq[k]], 10) +
                           ", the scene's " + gnum(q0[pq[k]], 10) + " (within " + gnum(kRecordedStartTol) + "; a run of another start?)");
  if (!u) return;
  for (size_t k = 0; k < un.size(); ++k)
    if (std::abs((*u)[pu[k]] - u0[pu[k]]) > kRecordedStartTol)
      throw w.at(line, "the first sample is not the scene's initial state: '" + un[k] + "' is " + gnum((*u)[pu[k]], 10) +
                           ", the scene's " + gnum(u0[pu[k]], 10) + " (within " + gnum(kRecordedStartTol) + ")");
}

// A quaternion of the file, its norm 1 within kRecordedUnitTol.
void checkUnit(const Where& w, long line, size_t col, const std::string& name, const Vec4& quat) {
  if (std::abs(quat.norm() - 1) > kRecordedUnitTol)
    throw w.at(line, col, name, "the quaternion's norm is " + gnum(quat.norm(), 10) + ", not 1 (within " + gnum(kRecordedUnitTol) + ")");
}

// Joint format: q (and u) of every row, internal order.
void readJointRows(const Where& w, const Model& m, const Header& h, const std::vector<std::vector<double>>& rows,
                   const std::vector<long>& lines, bool with_u, RecordedRun& r) {
  const std::vector<std::string> qn = m.qNames(), un = m.uNames();
  const std::vector<int> pq = m.qFilePermutation(), pu = m.uFilePermutation();
  for (size_t s = 0; s < rows.size(); ++s) {
    Eigen::VectorXd q(m.nq), u = Eigen::VectorXd::Zero(m.nu);
    for (size_t k = 0; k < qn.size(); ++k) q[pq[k]] = rows[s][h.col.at(qn[k])];
    if (with_u)
      for (size_t k = 0; k < un.size(); ++k) u[pu[k]] = rows[s][h.col.at(un[k])];
    for (const Body& b : m.bodies)
      if (const int k = jointQuat(b.joint.type); k >= 0) {
        const size_t file_k = std::find(pq.begin(), pq.end(), b.iq + k) - pq.begin();
        checkUnit(w, lines[s], h.col.at(qn[file_k]), qn[file_k], q.segment<4>(b.iq + k));
      }
    r.t.push_back(rows[s][0]);
    r.q.push_back(q);
    r.u.push_back(u);
  }
}

// Pose format: every body's logged pose, and q from the joints' relative poses (jointCoordinates).
void readPoseRows(const Where& w, const Model& m, const Header& h, const std::vector<std::vector<double>>& rows,
                  const std::vector<long>& lines, RecordedRun& r) {
  Eigen::VectorXd near = m.q0();
  for (size_t s = 0; s < rows.size(); ++s) {
    std::vector<Pose> poses(m.n());
    for (int i = 0; i < m.n(); ++i) {
      const std::string& b = m.bodies[i].name;
      const auto at = [&](const char* c) { return rows[s][h.col.at(b + "." + c)]; };
      poses[i].p = Vec3(at("x"), at("y"), at("z"));
      poses[i].quat = Vec4(at("qw"), at("qx"), at("qy"), at("qz"));
      checkUnit(w, lines[s], h.col.at(b + ".qw"), b + ".qw", poses[i].quat);
      poses[i].quat.normalize();
    }
    Eigen::VectorXd q(m.nq);
    for (int i = 0; i < m.n(); ++i) {
      const Body& b = m.bodies[i];
      const Mat3 R = quatToMatrix(poses[i].quat);
      const Mat3 Rp = b.parent < 0 ? Mat3::Identity() : quatToMatrix(poses[b.parent].quat);
      const Vec3 rp = b.parent < 0 ? Vec3::Zero() : poses[b.parent].p;
      const Vec3 x = Rp.transpose() * ((poses[i].p + R * b.joint.in_body) - (rp + Rp * b.joint.in_parent));
      jointCoordinates(b.joint, Rp.transpose() * R, x, near.data() + b.iq, q.data() + b.iq);
      r.max_joint_separation = std::max(r.max_joint_separation, jointSeparation(b.joint, x));
    }
    near = q;
    r.t.push_back(rows[s][0]);
    r.q.push_back(q);
    r.u.push_back(Eigen::VectorXd::Zero(m.nu));
    r.poses.push_back(std::move(poses));
  }
}

// Weights w_k of the derivative at t[s] of the polynomial through the samples
// t[a..a+n) (Lagrange: f'(t_s) ~ sum w_k f(t_k)), for any spacing.
std::vector<double> derivativeWeights(const std::vector<double>& t, size_t a, size_t n, size_t s) {
  std::vector<double> w(n, 0.0);
  for (size_t j = 0; j < n; ++j) {
    const size_t tj = a + j;
    if (tj == s) {
      for (size_t m = 0; m < n; ++m)
        if (a + m != s) w[j] += 1.0 / (t[s] - t[a + m]);
      continue;
    }
    double l = 1.0 / (t[tj] - t[s]);  // L_j'(t_s) = prod_{m != j, s} (t_s - t_m)/(t_j - t_m) / (t_j - t_s)
    for (size_t m = 0; m < n; ++m)
      if (a + m != tj && a + m != s) l *= (t[s] - t[a + m]) / (t[tj] - t[a + m]);
    w[j] = l;
  }
  return w;
}

// u at sample s from the derivative through `points` samples around it (the
// window shifted inside the file at its ends) of the joints' relative
// rotations and slides: w from R' R^T, x' (parent frame), then jointSpeeds.
void speedsAt(const Model& m, const RecordedRun& r, size_t s, size_t points, Eigen::VectorXd& u) {
  const size_t n = std::min(points, r.t.size());
  const size_t a = std::min(s >= n / 2 ? s - n / 2 : 0, r.t.size() - n);
  const std::vector<double> w = derivativeWeights(r.t, a, n, s);
  for (const Body& body : m.bodies) {
    const Joint& j = body.joint;
    Mat3 Rdot = Mat3::Zero();
    Vec3 xdot = Vec3::Zero();
    for (size_t k = 0; k < n; ++k) {
      const double* qk = r.q[a + k].data() + body.iq;
      Rdot += w[k] * relativeRotation(j, qk);
      xdot += w[k] * slideOffset(j, qk);
    }
    const double* qs = r.q[s].data() + body.iq;
    const Mat3 W = Rdot * relativeRotation(j, qs).transpose();
    const Vec3 om = 0.5 * Vec3(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1));
    jointSpeeds(j, qs, om, xdot, u.data() + body.iu);
  }
}

// T at (q, u) by the in-house kinematics.
double kineticEnergy(const Model& m, const double* q, const double* u, Workspace& ws) {
  formKinematics(m, q, u, ws);
  formEnergies(m, q, ws);
  return ws.kinetic;
}

// u at every sample by five-point differences (fourth order in the spacing h),
// and what the spacing does to the energy figure: the largest difference
// between the kinetic energies of the five-point and the three-point (second
// order) speeds, relative to the largest kinetic energy. That difference is
// the three-point estimate's error to leading order; the five-point's is
// O(h^2) smaller again (docs/plugins.md, "body poses").
void speedsByDifferences(const Model& m, RecordedRun& r) {
  Workspace ws(m);
  Eigen::VectorXd u3(m.nu);
  double dT = 0, Tmax = 0;
  for (size_t s = 0; s < r.t.size(); ++s) {
    speedsAt(m, r, s, kSpeedPoints, r.u[s]);
    speedsAt(m, r, s, 3, u3);
    const double T5 = kineticEnergy(m, r.q[s].data(), r.u[s].data(), ws), T3 = kineticEnergy(m, r.q[s].data(), u3.data(), ws);
    dT = std::max(dT, std::abs(T5 - T3));
    Tmax = std::max(Tmax, T5);
  }
  r.spacing_effect = Tmax > 0 ? dT / Tmax : 0;
}

// W_diss at every sample: the file's own `dissipated` column where it has one
// (an exact run's; issue 73, item 12: the quadrature over 10-ms samples put
// 2.6e-5 on an outside client's energy figure), else the trapezoid rule over
// the non-conservative power (joint and point dampers, minus the drives' tau u;
// theory.md eq. (M6)) at the samples.
void dissipatedWork(const Model& m, const Header& h, const std::vector<std::vector<double>>& rows, RecordedRun& r) {
  r.dissipated.assign(r.t.size(), 0.0);
  if (h.has("dissipated") && rows.size() == r.t.size()) {
    for (size_t s = 0; s < rows.size(); ++s) r.dissipated[s] = rows[s][h.col.at("dissipated")] - rows[0][h.col.at("dissipated")];
    r.dissipated_from = "the file's dissipated column";
    return;
  }
  if (!m.has_dampers) {
    r.dissipated_from = "none: the scene has no damper or drive";
    return;
  }
  Workspace ws(m);
  std::vector<double> power(r.t.size());
  for (size_t s = 0; s < r.t.size(); ++s) {
    formKinematics(m, r.q[s].data(), r.u[s].data(), ws);
    if (m.has_control) controlTorques(m, r.t[s], r.q[s].data(), r.u[s].data(), ws.control);
    power[s] = nonConservativePower(m, ws, r.u[s].data());
  }
  for (size_t s = 1; s < r.t.size(); ++s) r.dissipated[s] = r.dissipated[s - 1] + 0.5 * (r.t[s] - r.t[s - 1]) * (power[s - 1] + power[s]);
  r.dissipated_from = "the trapezoid rule over the samples' non-conservative power (its error is second order in the spacing)";
  if (m.has_control && m.control_period > 0)
    r.dissipated_from += "; the sampled controller's torques as the law gives them at each sample, not as it held them";
}

RecordedRun readRecorded(const std::string& name, const std::string& path, const Model& m) {
  const Where w{path};
  RecordedRun r;
  r.name = name, r.file = path;
  CsvText text;
  try {
    text = readCsvText(path, "recorded run");
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(e.what());
  }
  const std::vector<std::string>& lines = text.lines;
  if (lines.empty()) throw std::invalid_argument(path + ": empty");
  r.sha256 = sha256Hex(text.bytes);
  const size_t head = readDeclared(w, lines, r);
  const Header h = readHeader(w, m, lines[head], static_cast<long>(head) + 1);
  bool with_u = false;
  r.format = formatOf(w, m, h, static_cast<long>(head) + 1, with_u);
  std::vector<long> lineno;
  const std::vector<std::vector<double>> rows = readRows(w, lines, head + 1, h, lineno);
  if (r.format == "joint-coordinates") readJointRows(w, m, h, rows, lineno, with_u, r);
  else readPoseRows(w, m, h, rows, lineno, r);
  checkStart(w, m, lineno[0], r.q[0], with_u ? &r.u[0] : nullptr);
  r.speeds = with_u ? "file" : "five-point differences (fourth order in the spacing)";
  if (!with_u) speedsByDifferences(m, r);
  dissipatedWork(m, h, rows, r);
  return r;
}


double medianSpacing(const std::vector<double>& t) {
  std::vector<double> d;
  for (size_t k = 1; k < t.size(); ++k) d.push_back(t[k] - t[k - 1]);
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

// x at t between samples a and a + 1 (weight f of the later), quaternion blocks normalized.
Eigen::VectorXd lerpQ(const Model& m, const Eigen::VectorXd& x0, const Eigen::VectorXd& x1, double f) {
  Eigen::VectorXd x = (1 - f) * x0 + f * x1;
  for (const Body& b : m.bodies)
    if (const int k = jointQuat(b.joint.type); k >= 0) {
      const Eigen::Vector4d a = x0.segment<4>(b.iq + k), c = x1.segment<4>(b.iq + k);
      x.segment<4>(b.iq + k) = ((1 - f) * a + f * (a.dot(c) < 0 ? -c : c)).normalized();
    }
  return x;
}

std::vector<Pose> lerpPoses(const std::vector<Pose>& p0, const std::vector<Pose>& p1, double f) {
  std::vector<Pose> p(p0.size());
  for (size_t i = 0; i < p0.size(); ++i) {
    p[i].p = (1 - f) * p0[i].p + f * p1[i].p;
    const Vec4 c = p0[i].quat.dot(p1[i].quat) < 0 ? Vec4(-p1[i].quat) : p1[i].quat;
    p[i].quat = ((1 - f) * p0[i].quat + f * c).normalized();
  }
  return p;
}

}  // namespace

Integrator recordedScheme() {
  Integrator id;
  if (findIntegrator("recorded", id)) return id;
  // Listed as the in-house engine's so that a plan's case of a recorded run passes the checks every case
  // passes; simulate refuses it (no step function, no GSL stepper).
  return addIntegrator({Integrator::RK4, "recorded", {Engine::InHouse}, true, nullptr, nullptr,
                        "samples read from a file (compare --run, a plan's runs): no integrator of ours; its step is "
                        "the file's median spacing", "x"});
}

Method addRecordedRun(const std::string& name, const std::string& path, const Model& m) {
  if (!isSceneName(name))
    throw std::invalid_argument("run name '" + printable(name, 40) + "': letters, digits, '_' and '-', 1 to 64 of them");
  Method taken;
  if (findMethod(name, taken)) throw std::invalid_argument("run name '" + printable(name, 40) + "': a method of that name exists");
  Entry e{readRecorded(name, path, m), "", Method::Classical};
  recordedScheme();
  entries().push_back(std::move(e));
  Entry& row = entries().back();
  static std::deque<std::string> summaries;  // the rows' summaries (a row keeps a pointer)
  summaries.push_back("recorded run " + path + " (" + row.run.format + ")");
  MethodInfo added;  // no factory: nothing runs, its samples are read (runTrajectory)
  added.name = row.run.name.c_str();
  added.summary = summaries.back().c_str();
  // Not tree_only: a recorded run has no u' to refuse; on a mechanism it is judged by its
  // samples, its loops measured by our g(q) and G u (recordedTrajectory).
  added.tree_only = false;
  row.id = addMethod(added);
  return row.id;
}

const RecordedRun* recordedRun(Method method) {
  const Entry* e = findEntry(method);
  return e ? &e->run : nullptr;
}

Trajectory recordedTrajectory(const Model& m, const CheckedRunSpec& checked_spec) {
  const RunSpec& spec = checked_spec;
  Entry* e = findEntry(spec.method);
  if (!e) throw std::logic_error("recordedTrajectory: not a recorded run");
  const RecordedRun& r = e->run;
  RunSpec run = spec;
  run.integrator = recordedScheme();
  run.dt = std::stod(gnum(medianSpacing(r.t), 12));  // 0.01, not 0.009999999999999787 (a difference of sums of 0.01)
  Trajectory tr = makeTrajectory(m, run);
  Workspace ws(m);
  std::optional<LoopMeter> meter;  // a mechanism's violation at the samples, by our g(q) and G u
  if (!m.loops.empty()) meter.emplace(m), tr.has_loops = true;
  const long N = outputIntervals(spec.t_end, spec.output_dt);
  const double eps = 1e-9;
  size_t a = 0;
  long interpolated = 0, taken = 0;
  for (long k = 0; k <= N; ++k) {
    const double tg = static_cast<double>(k) * spec.output_dt;
    if (tg > r.t.back() + eps * std::max(1.0, tg)) break;
    while (a + 1 < r.t.size() && r.t[a + 1] <= tg + eps * std::max(1.0, tg)) ++a;
    const bool exact = std::abs(r.t[a] - tg) <= eps * std::max(1.0, tg) || a + 1 == r.t.size();
    const double f = exact ? 0.0 : (tg - r.t[a]) / (r.t[a + 1] - r.t[a]);
    const size_t b = exact ? a : a + 1;
    (exact ? taken : interpolated) += 1;
    const Eigen::VectorXd q = lerpQ(m, r.q[a], r.q[b], f), u = (1 - f) * r.u[a] + f * r.u[b];
    const double W = (1 - f) * r.dissipated[a] + f * r.dissipated[b];
    if (meter) meter->record(q.data(), u.data(), tr.loops);
    if (r.poses.empty()) {
      appendStateSample(tr, m, ws, tg, q.data(), u.data(), W);
      continue;
    }
    formKinematics(m, q.data(), u.data(), ws);
    formEnergies(m, q.data(), ws);
    appendSample(tr, m, tg, q.data(), u.data(), lerpPoses(r.poses[a], r.poses[b], f), {ws.energy(), ws.kinetic, W});
  }
  e->grid = interpolated == 0 ? "every grid time is a sample"
                              : "linear between samples (quaternions normalized) at " + std::to_string(interpolated) + " of " +
                                    std::to_string(interpolated + taken) + " grid times";
  tr.run_time_s = r.cpu_s;
  tr.steps = static_cast<long>(r.t.size()) - 1;
  if (!r.poses.empty()) tr.max_joint_separation = r.max_joint_separation;
  if (r.t.back() < spec.t_end - eps * std::max(1.0, spec.t_end))
    markFailed(tr, r.t.back(), Failure::EndedEarly, "the recorded run ends at t = " + gnum(r.t.back(), 10) + " s, before " + gnum(spec.t_end) + " s");
  return tr;
}

nlohmann::json recordedSource(Method method) {
  const Entry* e = findEntry(method);
  if (!e) return nullptr;
  const RecordedRun& r = e->run;
  nlohmann::json j = {{"recorded", r.file},   {"sha256", r.sha256}, {"format", r.format}, {"speeds", r.speeds},
                      {"samples", r.t.size()}, {"grid", e->grid},    {"declared", r.declared},
                      {"dissipated", r.dissipated_from}};
  if (r.speeds != "file") j["speeds_spacing_effect"] = r.spacing_effect;
  return j;
}

}  // namespace em
