// The ensemble's distributions (docs/sweep.md, "ensemble"): for every scene x
// method x integrator x setting x divergence metric x threshold, how many
// members crossed, how many failed, the quartiles of the crossing times and
// the median's 95 % interval over all members. A member that never crosses is
// censored: later than t_end (+inf in the order statistics), never given a
// time, as tools/ensemble_summary.py counts it. The reference horizon (the check against the reference)
// gets the same rows under the method name "reference-horizon".
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

#include "io/csv.hpp"
#include "solver/text.hpp"
#include "sweep/sweep.hpp"

namespace em {

namespace {

using GroupKey = std::tuple<std::string, std::string, std::string, SettingKind, double>;  // scene, method, integrator, kind, setting

struct Metric {
  const char* name;
  size_t threshold;          ///< index into kCaseThresholds
  FirstTimes CaseRecord::*times;
  bool joint;  ///< joint coordinates: only where the engines share them
};
const Metric kMetrics[] = {{"pose", 0, &CaseRecord::pose_beyond, false},
                           {"pose", 1, &CaseRecord::pose_beyond, false},
                           {"joint", 0, &CaseRecord::coord_beyond, true},
                           {"joint", 1, &CaseRecord::coord_beyond, true}};
static_assert(kCaseThresholds.size() == 2, "kMetrics: one pose and one joint row per threshold");

Distribution distributionOf(const std::vector<const CaseRecord*>& members, const Metric& metric) {
  Distribution d;
  std::vector<double> times;
  for (const CaseRecord* r : members) {
    ++d.members;
    if (r->status != Outcome::Ok) ++d.failed;
    const std::optional<double>& t = (r->*metric.times)[metric.threshold];
    if (t) ++d.diverged;
    times.push_back(t ? *t : HUGE_VAL);  // never crossed: later than t_end, censored
  }
  d.min = quantile(times, 0), d.q1 = quantile(times, 0.25), d.median = quantile(times, 0.5);
  d.q3 = quantile(times, 0.75), d.max = quantile(times, 1);
  d.median_ci = medianInterval(times);
  return d;
}

}  // namespace

std::vector<EnsembleRow> ensembleRows(const std::vector<CaseRecord>& records) {
  std::map<GroupKey, std::vector<const CaseRecord*>> groups;
  std::vector<GroupKey> order;  // first appearance: plan order
  for (const CaseRecord& r : records) {
    if (r.role == CaseRole::Reference || !r.has_error) continue;
    const GroupKey key{r.scene, r.role == CaseRole::Check ? "reference-horizon" : r.method, r.integrator, r.setting_kind, r.setting};
    auto& g = groups[key];
    if (g.empty()) order.push_back(key);
    g.push_back(&r);
  }
  std::vector<EnsembleRow> rows;
  for (const GroupKey& key : order) {
    const std::vector<const CaseRecord*>& members = groups[key];
    const bool joint_shared = std::isfinite(members.front()->max_coord);
    for (const Metric& metric : kMetrics) {
      if (metric.joint && !joint_shared) continue;
      EnsembleRow row;
      std::tie(row.scene, row.method, row.integrator, row.setting_kind, row.setting) = key;
      row.metric = metric.name;
      row.threshold = kCaseThresholds[metric.threshold];
      row.d = distributionOf(members, metric);
      rows.push_back(row);
    }
  }
  return rows;
}

std::string ensembleCsv(const std::vector<EnsembleRow>& rows) {
  auto opt = [](const std::optional<double>& x) { return !x ? std::string() : std::isinf(*x) ? std::string("inf") : gnum(*x, 17); };
  using C = CsvColumn<EnsembleRow>;
  static const std::vector<C> columns = {
      {"scene", [](const EnsembleRow& r) { return r.scene; }},
      {"method", [](const EnsembleRow& r) { return r.method; }},
      {"integrator", [](const EnsembleRow& r) { return r.integrator; }},
      {"setting_kind", [](const EnsembleRow& r) { return std::string(settingKindName(r.setting_kind)); }},
      {"setting", [](const EnsembleRow& r) { return gnum(r.setting, 17); }},
      {"metric", [](const EnsembleRow& r) { return r.metric; }},
      {"threshold", [](const EnsembleRow& r) { return gnum(r.threshold); }},
      {"members", [](const EnsembleRow& r) { return std::to_string(r.d.members); }},
      {"diverged", [](const EnsembleRow& r) { return std::to_string(r.d.diverged); }},
      {"failed", [](const EnsembleRow& r) { return std::to_string(r.d.failed); }},
      {"median_s", [opt](const EnsembleRow& r) { return opt(r.d.median); }},
      {"q1_s", [opt](const EnsembleRow& r) { return opt(r.d.q1); }},
      {"q3_s", [opt](const EnsembleRow& r) { return opt(r.d.q3); }},
      {"min_s", [opt](const EnsembleRow& r) { return opt(r.d.min); }},
      {"max_s", [opt](const EnsembleRow& r) { return opt(r.d.max); }},
      {"median_lo_s", [opt](const EnsembleRow& r) { return opt(r.d.median_ci->first); }},
      {"median_hi_s", [opt](const EnsembleRow& r) { return opt(r.d.median_ci->second); }}};
  return csvTable(columns, rows);
}

std::string ensembleTable(const std::vector<EnsembleRow>& rows) {
  std::ostringstream o;
  o << "## Ensemble: when the members cross each threshold\n\n"
       "Times (s) at which each member's error against its own reference first exceeds the threshold: median "
       "[quartiles] (min - max) over all members, a member that never crosses counted as later than t_end "
       "(`> t_end`: censored, never given a time); `crossed` counts those that did, `failed` runs that "
       "stopped (a failure counts as crossing at its time). `reference-horizon` is the reference's own check.\n\n"
       "| scene | method | integrator | setting | metric | threshold | members | crossed | failed | median [q1, q3] | min - max |\n"
       "|---|---|---|---:|---|---:|---:|---:|---:|---|---|\n";
  auto t = [](const std::optional<double>& x) { return !x ? std::string("-") : std::isinf(*x) ? std::string("> t_end") : gnum(*x, 3); };
  for (const EnsembleRow& r : rows)
    o << "| " << r.scene << " | " << r.method << " | " << r.integrator << " | " << gnum(r.setting) << " | " << r.metric
      << " | " << gnum(r.threshold) << " | " << r.d.members << " | " << r.d.diverged << " | " << r.d.failed << " | "
      << t(r.d.median) << " [" << t(r.d.q1) << ", " << t(r.d.q3) << "] | " << t(r.d.min) << " - " << t(r.d.max) << " |\n";
  return o.str() + "\n";
}

}  // namespace em

namespace em {

namespace {

// The member's reference exponent by (scene, member).
std::map<std::pair<std::string, int>, double> exponents(const std::vector<CaseRecord>& records) {
  std::map<std::pair<std::string, int>, double> out;
  for (const CaseRecord& r : records)
    if (r.role == CaseRole::Reference && r.lyapunov_per_s) out[{r.scene, r.member}] = *r.lyapunov_per_s;
  return out;
}

}  // namespace

std::vector<Prediction> predictions(const std::vector<CaseRecord>& records) {
  const auto chi = exponents(records);
  std::vector<Prediction> out;
  for (const CaseRecord& r : records) {
    if (r.role != CaseRole::Run || !r.has_error || !r.t0 || !r.pose_by_t0) continue;
    const auto l = chi.find({r.scene, r.member});
    if (l == chi.end()) continue;
    for (size_t i = 0; i < kCaseThresholds.size(); ++i) {
      const double threshold = kCaseThresholds[i];
      Prediction p;
      p.record = &r;
      p.threshold = threshold;
      p.chi = l->second;
      p.e0 = *r.pose_by_t0;
      p.measured = r.pose_beyond[i];
      if (p.chi > 0 && p.e0 > 0 && p.e0 < threshold) p.predicted = *r.t0 + std::log(threshold / p.e0) / p.chi;
      out.push_back(p);
    }
  }
  return out;
}

std::string predictionCsv(const std::vector<Prediction>& rows) {
  auto opt = [](const std::optional<double>& x) { return x ? gnum(*x, 17) : std::string(); };
  using C = CsvColumn<Prediction>;
  static const std::vector<C> columns = {
      {"scene", [](const Prediction& p) { return p.record->scene; }},
      {"member", [](const Prediction& p) { return std::to_string(p.record->member); }},
      {"method", [](const Prediction& p) { return p.record->method; }},
      {"integrator", [](const Prediction& p) { return p.record->integrator; }},
      {"setting", [](const Prediction& p) { return gnum(p.record->setting, 17); }},
      {"threshold", [](const Prediction& p) { return gnum(p.threshold); }},
      {"t0_s", [opt](const Prediction& p) { return opt(p.record->t0); }},
      {"pose_error_by_t0_rad", [](const Prediction& p) { return gnum(p.e0, 17); }},
      {"lyapunov_per_s", [](const Prediction& p) { return gnum(p.chi, 17); }},
      {"predicted_s", [opt](const Prediction& p) { return opt(p.predicted); }},
      {"measured_s", [opt](const Prediction& p) { return opt(p.measured); }},
      {"status", [](const Prediction& p) { return std::string(outcomeName(p.record->status)); }}};
  return csvTable(columns, rows);
}

std::string predictionTable(const std::vector<Prediction>& rows) {
  // Per method x integrator x setting x threshold: members with both times, and
  // the quartiles of measured / predicted.
  using Key = std::tuple<std::string, std::string, std::string, double, double>;
  std::map<Key, std::vector<double>> ratios;
  std::map<Key, int> members;
  std::vector<Key> order;
  for (const Prediction& p : rows) {
    const Key k{p.record->scene, p.record->method, p.record->integrator, p.record->setting, p.threshold};
    if (!members.count(k)) order.push_back(k);
    ++members[k];
    if (p.predicted && p.measured) ratios[k].push_back(*p.measured / *p.predicted);
  }
  std::ostringstream o;
  o << "## Divergence times predicted from the Lyapunov exponent\n\n"
       "Each member's time to exceed the threshold predicted as t0 + ln(threshold / e(t0)) / chi, from its "
       "largest pose error e(t0) up to t0 = t_end / 10 and its reference's Lyapunov exponent chi; `both` counts members "
       "with a prediction and a measured crossing; measured / predicted: median [quartiles].\n\n"
       "| scene | method | integrator | setting | threshold | members | both | measured / predicted |\n"
       "|---|---|---|---:|---:|---:|---:|---|\n";
  auto t = [](const std::optional<double>& x) { return x ? gnum(*x, 3) : std::string("-"); };
  for (const Key& k : order) {
    const std::vector<double>& x = ratios[k];
    o << "| " << std::get<0>(k) << " | " << std::get<1>(k) << " | " << std::get<2>(k) << " | " << gnum(std::get<3>(k))
      << " | " << gnum(std::get<4>(k)) << " | " << members[k] << " | " << x.size() << " | " << t(quantile(x, 0.5)) << " ["
      << t(quantile(x, 0.25)) << ", " << t(quantile(x, 0.75)) << "] |\n";
  }
  return o.str() + "\n";
}

}  // namespace em
