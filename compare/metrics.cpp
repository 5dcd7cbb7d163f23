#include "compare/metrics.hpp"
#include "solver/control.hpp"

#include "solver/text.hpp"

#include <algorithm>
#include <cmath>

namespace em {

EnergyScale energyScaleOf(const Trajectory& ref) {
  double T = 0, Vlo = INFINITY, Vhi = -INFINITY;  // non-finite samples (a blown-up reference) carry no scale
  for (size_t k = 0; k < ref.kinetic.size(); ++k) {
    if (std::isfinite(ref.kinetic[k])) T = std::max(T, ref.kinetic[k]);
    if (k < ref.energy.size() && std::isfinite(ref.energy[k]) && std::isfinite(ref.kinetic[k])) {
      const double V = ref.energy[k] - ref.kinetic[k];
      Vlo = std::min(Vlo, V), Vhi = std::max(Vhi, V);
    }
  }
  const double E0 = !ref.energy.empty() && std::isfinite(ref.energy[0]) ? std::abs(ref.energy[0]) : 0.0;
  const double V_range = Vhi > Vlo ? Vhi - Vlo : 0.0;
  if (T > 0 && T > kRestKinetic * std::max(E0, V_range)) return {T, kKineticScale};
  const std::string rest = T > 0 ? "the reference's kinetic energy, at most " + gnum(T, 3) + " J, is round-off: the scene rests; " : "";
  if (E0 > 0) return {E0, rest + "|E(0)|"};
  if (V_range > 0) return {V_range, rest + "the range of the reference's potential energy"};
  return {1.0, rest + "1 J: the reference's energies are all 0"};
}

double energyScale(const Trajectory& ref) { return energyScaleOf(ref).joules; }

namespace {

// Angle coordinates (not a quaternion's, not a displacement), when both runs name the same.
std::vector<int> angleCoordinates(const Trajectory& run, const Trajectory& ref) {
  if (run.q_names != ref.q_names || run.angle_coords != ref.angle_coords) return {};
  return run.angle_coords;
}

template <class F>
Peak peakOf(const std::vector<double>& t, size_t n, F&& value) {
  Peak p;  // {0, 0} for an empty series
  for (size_t k = 0; k < n; ++k) {
    const double v = value(k);
    if (k == 0 || v > p.value || std::isnan(v)) { p.value = v; p.t = t[k]; }
    if (std::isnan(v)) break;  // NaN is the worst value: keep its time
  }
  return p;
}

Peak peakOf(const std::vector<double>& t, const std::vector<double>& v) {
  return peakOf(t, v.size(), [&](size_t k) { return v[k]; });
}

}  // namespace

ErrorSeries errorSeries(const Trajectory& run, const Trajectory& ref, double energy_scale) {
  ErrorSeries s;
  const size_t n = std::min(run.size(), ref.size());
  const std::vector<int> angles = angleCoordinates(run, ref);
  for (size_t k = 0; k < n; ++k) {
    double rot = 0, pos = 0, crd = 0;
    for (size_t b = 0; b < run.poses[k].size(); ++b) {
      const Pose &p = run.poses[k][b], &r = ref.poses[k][b];
      rot = std::max(rot, rotationAngleBetween(quatToMatrix(r.quat), quatToMatrix(p.quat)));
      pos = std::max(pos, (p.p - r.p).norm());
    }
    for (int i : angles) crd = std::max(crd, std::abs(run.q[k][i] - ref.q[k][i]));
    s.t.push_back(run.t[k]);
    s.pose_rad.push_back(rot);
    s.position_m.push_back(pos);
    if (!angles.empty()) s.coord_rad.push_back(crd);
    // The energy balance: what the dampers took is not an error (docs/theory.md §5).
    s.energy_rel.push_back(std::abs(run.energy[k] + run.dissipated[k] - run.energy[0]) / energy_scale);
  }
  return s;
}

std::optional<double> firstExceedance(const std::vector<double>& t, const std::vector<double>& err, double threshold) {
  for (size_t k = 0; k < err.size(); ++k)
    if (!(err[k] <= threshold)) return t[k];  // NaN counts as exceeded
  return std::nullopt;
}

std::vector<std::optional<double>> referenceHorizon(const Trajectory& ref, const Trajectory& tight,
                                                    const std::vector<double>& thresholds) {
  const ErrorSeries s = errorSeries(ref, tight, energyScale(ref));
  std::vector<std::optional<double>> h;
  for (double th : thresholds) h.push_back(firstExceedance(s.t, s.pose_rad, th));
  return h;
}

MethodMetrics measureRun(const Trajectory& run, const Trajectory& ref, const std::vector<double>& thresholds,
                         const std::vector<std::optional<double>>& horizon, double energy_scale) {
  MethodMetrics m;
  static_cast<RunEnd&>(m) = run;  // how it ended and its cost, whole
  m.run = run.run;
  m.max_joint_separation = run.max_joint_separation;
  m.impacts = run.impact_count;
  m.series = errorSeries(run, ref, energy_scale);
  const ErrorSeries& s = m.series;
  m.pose = peakOf(s.t, s.pose_rad);
  m.position = peakOf(s.t, s.position_m);
  m.coords_shared = !s.coord_rad.empty();
  if (m.coords_shared) m.coord = peakOf(s.t, s.coord_rad);
  m.energy = peakOf(s.t, s.energy_rel);
  m.energy_error_final = s.energy_rel.empty() ? 0 : s.energy_rel.back();
  m.dissipated_final = run.dissipated.empty() ? 0 : run.dissipated.back();
  for (size_t i = 0; i < thresholds.size(); ++i) {
    auto first = firstExceedance(s.t, s.pose_rad, thresholds[i]);
    auto first_q = m.coords_shared ? firstExceedance(s.t, s.coord_rad, thresholds[i]) : std::nullopt;
    // A run that stopped before crossing has no solution after its failure time.
    if (run.failed() && !first) first = run.failure_time;
    if (run.failed() && m.coords_shared && !first_q) first_q = run.failure_time;
    m.divergence_time_s.push_back(first);
    m.coord_divergence_time_s.push_back(first_q);
    m.divergence_meaningful.push_back(first && (!horizon[i] || *first < *horizon[i]));
  }
  if (!run.diag.empty()) {
    m.has_diagnostics = true;
    const auto& d = run.diag;
    const size_t n = d.size();
    m.orth_err = peakOf(run.t, n, [&](size_t k) { return d[k].orth_err; });
    m.offdiag_rel = peakOf(run.t, n, [&](size_t k) { return d[k].offdiag_rel; });
    m.max_Omega = peakOf(run.t, n, [&](size_t k) { return d[k].max_Omega; });
    m.inv_err = peakOf(run.t, n, [&](size_t k) { return d[k].inv_err; });
    m.eigen = run.eigen;
  }
  return m;
}

Outcome outcomeOf(const MethodMetrics& m, const std::optional<double>& horizon) {
  if (m.failed()) return Outcome::Failed;
  const ErrorSeries& s = m.series;
  for (size_t k = 0; k < s.t.size() && (!horizon || s.t[k] < *horizon); ++k)
    if (!(s.pose_rad[k] <= kWrongRad)) return Outcome::Wrong;  // NaN counts as beyond
  return Outcome::Ok;
}

std::optional<Tracking> trackingOf(const Model& m, const Trajectory& run) {
  std::vector<const Body*> pd;
  for (const Body& b : m.bodies)
    if (b.joint.control && b.joint.control->type == ControlType::Pd) pd.push_back(&b);
  if (pd.empty()) return std::nullopt;
  Tracking tr;
  const std::vector<std::string> names = m.qNames();
  double sum = 0;
  long count = 0;
  double qs[6], qsdot[6];
  for (size_t k = 0; k < run.t.size(); ++k)
    for (const Body* b : pd) {
      targetAt(b->joint.control->target, run.t[k], qs, qsdot);
      for (int j = 0; j < b->nu(); ++j) {
        const double e = std::abs(run.q[k][b->file_iq + j] - qs[j]);
        sum += e * e, ++count;
        if (e > tr.max) tr.max = e, tr.max_t = run.t[k], tr.worst = names[static_cast<size_t>(b->file_iq + j)];
      }
    }
  tr.rms = count ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
  return tr;
}

ImpactCheck checkImpacts(const Trajectory& run, const Trajectory& ref) {
  ImpactCheck c;
  c.count = run.impact_count;
  c.reference_count = ref.impact_count;
  for (const Impact& i : run.impacts) c.overshoot_max = std::max(c.overshoot_max, i.overshoot), c.duration_max = std::max(c.duration_max, i.duration);
  const size_t n = std::min(run.impacts.size(), ref.impacts.size());
  for (size_t k = 0; k < n; ++k) {
    const Impact &a = run.impacts[k], &b = ref.impacts[k];
    if (a.coordinate != b.coordinate) break;  // the sequences part: no more pairs
    c.compared = static_cast<long>(k) + 1;
    if (k == 0) c.first_time_error = a.t - b.t, c.first_rebound_error = a.u_after - b.u_after;
    c.time_error_max = std::max(c.time_error_max, std::abs(a.t - b.t));
    c.rebound_error_max = std::max(c.rebound_error_max, std::abs(a.u_after - b.u_after));
  }
  return c;
}

}  // namespace em
