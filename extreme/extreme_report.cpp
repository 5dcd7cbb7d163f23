// The gallery's outputs: the summary JSON, the diagnosis of each failure, the
// Markdown page and the check against a recorded summary (compare/extreme.hpp).
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <stdexcept>

#include "extreme/extreme.hpp"
#include "compare/provenance.hpp"
#include "compare/report.hpp"
#include "io/json_input.hpp"

namespace em {

using json = nlohmann::json;

namespace {


json eigenJson(const ExtremeEntry& e) {
  if (!e.eigenfactor) return nullptr;
  const EigenStats& s = e.eigen;
  return {{"min_gap", finiteOrNull(s.min_gap)},
          {"min_gap_t", s.min_gap_time},
          {"max_abs_Omega", s.max_abs_Omega},
          {"jacobi_sweeps", s.jacobi_sweeps},
          {"jacobi_max_sweeps", s.jacobi_max_sweeps},
          {"block_merges", s.block_merges},
          {"block_splits", s.block_splits},
          {"first_drift", e.first_drift.empty() ? json(nullptr) : json({{"name", e.first_drift}, {"t", e.first_drift_t}})}};
}

// A mechanism's run: how far its closures opened (our g and G u at its steps
// and samples) and the rank it saw (null: an engine's); null for a tree.
json loopsJson(const ExtremeEntry& e) {
  if (!e.has_loops) return nullptr;
  const LoopStats& l = e.loops;
  return {{"max_position_violation_m", l.position_m}, {"max_position_violation_rad", l.position_rad},
          {"max_velocity_violation_m_per_s", l.velocity_m}, {"rank", l.rank_max < 0 ? json(nullptr) : json(l.rank_max)},
          {"rank_min", l.rank_min < 0 ? json(nullptr) : json(l.rank_min)}};
}

json entryJson(const ExtremeEntry& e) {
  return {{"name", e.method},           {"outcome", outcomeName(e.outcome)},
          {"failure", e.outcome == Outcome::Failed ? failureJson(e.failedAt(), e.failure_kind, e.failure, e.failure_cond_A) : json(nullptr)},         {"diverged_" + thresholdKey(kDivergedRad) + "_s", orNull(e.diverged_at)},
          {"wrong_at_s", orNull(e.wrong_at)}, {"max_pose_error_rad", finiteOrNull(e.max_pose)},
          {"energy_error_max", finiteOrNull(e.max_energy)}, {"run_time_s", e.run_time_s},
          {"steps", e.steps},           {"rhs_evals", e.rhs_evals},
          {"step_retries", e.step_retries},
          {"eigen", eigenJson(e)},
          {"loops", loopsJson(e)}};
}

json runJson(const ExtremeRun& r) {
  json methods = json::array();
  for (const ExtremeEntry& e : r.entries) methods.push_back(entryJson(e));
  return {{"setting", r.setting.key()},
          {"label", r.setting.label()},
          {"t_end", r.t_end},
          {"reference", {{"tolerance", r.reference_tol}, {"status", r.reference_status}, {"failure", r.reference_failure}}},
          {"horizon_wrong_s", orNull(r.horizon_wrong)},
          {"report", r.report},
          {"methods", methods}};
}

}  // namespace

json extremeJson(const std::vector<ExtremeCaseResult>& cases) {
  json list = json::array();
  for (const ExtremeCaseResult& c : cases) {
    json runs = json::array();
    for (const ExtremeRun& r : c.runs) runs.push_back(runJson(r));
    list.push_back({{"name", c.name},
                    {"scene", sceneSourceJson(c.source)},
                    {"why", c.why},
                    {"nu", c.nu},
                    {"cond_A0", finiteOrNull(c.cond_A0)},
                    {"lambda_min0", c.lambda_min0},
                    {"lambda_max0", c.lambda_max0},
                    {"runs", runs}});
  }
  return {{"format", "eigenmass-extreme/1"}, {"provenance", provenance()}, {"cases", list}};
}

namespace {

std::string sci(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2g", x);
  return b;
}

std::string secs(double t) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g s", t);
  return b;
}

// The diagnostics of a run, as facts: retried steps, and an eigenfactor run's gap, |Omega|, sweeps, drift.
std::string eigenFacts(const ExtremeEntry& e, const ExtremeCaseResult& c) {
  const std::string retries =
      e.step_retries > 0 ? std::to_string(e.step_retries) + " steps retried smaller after a failed trial stage" : "";
  if (!e.eigenfactor || !std::isfinite(e.eigen.min_gap)) return retries;
  std::string s = "smallest eigenvalue gap " + sci(e.eigen.min_gap) + " (" + sci(e.eigen.min_gap / c.lambda_max0) +
                  " of the largest eigenvalue at t = 0) at " + secs(e.eigen.min_gap_time) + ", |Omega| up to " +
                  sci(e.eigen.max_abs_Omega);
  if (e.eigen.jacobi_sweeps > 0) s += ", " + std::to_string(e.eigen.jacobi_sweeps) + " Jacobi sweeps";
  if (!e.first_drift.empty())
    s += "; first drift: " + e.first_drift + " above " + sci(kDriftBound) + " at " + secs(e.first_drift_t);
  return retries.empty() ? s : s + "; " + retries;
}

// An ok run whose energy error exceeds this (relative) gets a line anyway:
// pose alone judges the outcome, and a run can stay near the reference while
// its energy is far off.
constexpr double kEnergyNote = 1e-2;

// A run met a near-crossing when its smallest gap fell below this fraction of
// the largest eigenvalue and the eigenvectors turned faster than
// kNearCrossingOmega (1/s, a hundred times a pendulum's own rates): a small
// gap alone is not one (thin_rods: gap 0.03 beside an eigenvalue of 8e-11,
// |Omega| 1).
constexpr double kNearCrossingRel = 1e-3;
constexpr double kNearCrossingOmega = 1e2;
// cond(A) beyond which an eigenvalue's drift below zero is put down to conditioning.
constexpr double kIllConditioned = 1e6;

std::string reasonOf(const ExtremeEntry& e, const ExtremeCaseResult& c) {
  const bool near_crossing = e.eigenfactor && e.eigen.min_gap < kNearCrossingRel * c.lambda_max0 &&
                             e.eigen.max_abs_Omega > kNearCrossingOmega;
  const double cond = std::isfinite(e.failure_cond_A) ? e.failure_cond_A : c.cond_A0;
  switch (e.failure_kind) {
    case Failure::EigenGap: return "two eigenvalues came within the gap floor: a crossing";
    case Failure::NonPositiveEigenvalue:
      if (near_crossing) return "an integrated eigenvalue went through zero after a near-crossing";
      if (cond > kIllConditioned) return "the smallest eigenvalue, 1/" + sci(cond) + " of the largest, drifted below zero";
      return "an integrated eigenvalue went through zero: the step was too large for the eigenvalue rates";
    case Failure::JacobiNotConverged: return "C had drifted too far from orthogonal for the Jacobi correction";
    case Failure::RefinementDiverged: return "the eigenfactors had drifted too far from A for the residual correction to contract";
    case Failure::RefinementNotConverged: return "the residual corrections contracted too slowly to reach classical's u'";
    case Failure::BlowUp: return "the speeds grew beyond the blow-up bound: the step was unstable";
    case Failure::NotPositiveDefinite:
    case Failure::Singular: return "A was singular to working precision there";
    case Failure::IntegratorStopped:
    case Failure::StepUnderflow: return "the adaptive step collapsed (" + std::to_string(e.steps) + " steps)";
    case Failure::NonFinite: return "the state or its rate stopped being finite";
    case Failure::Engine: return "the engine gave up";
    case Failure::Plugin: return "the plugin's u' failed, crashed or hung";
    case Failure::EndedEarly: return "the recorded run ends there";
    case Failure::LoopsOpen: return "the loops opened: a singular position, or the formulation drifted";
    case Failure::None: break;
  }
  return "";
}

}  // namespace

std::string diagnosis(const ExtremeEntry& e, const ExtremeCaseResult& c, const ExtremeRun& run) {
  if (e.outcome == Outcome::Ok) {
    if (!(e.max_energy > kEnergyNote)) return "";
    return "ok by the pose, but its energy error reached " + sci(e.max_energy) + " of the energy scale" +
           (eigenFacts(e, c).empty() ? "." : "; " + eigenFacts(e, c) + ".");
  }
  std::string s;
  if (e.outcome == Outcome::Wrong) {
    s = "completed, but was " + gnum(kWrongRad) + " rad from the reference at " + secs(e.wrong_at.value_or(0)) +
        (run.horizon_wrong ? ", before the reference horizon " + secs(*run.horizon_wrong) : " (the reference horizon is beyond t_end)");
  } else {
    s = "stopped at " + secs(e.failure_time) + " (" + failureName(e.failure_kind) + "): " + reasonOf(e, c);
    if (std::isfinite(e.failure_cond_A)) s += "; cond(A) there " + sci(e.failure_cond_A);
  }
  const std::string facts = eigenFacts(e, c);
  return facts.empty() ? s + "." : s + "; " + facts + ".";
}

namespace {

std::string cell(const std::optional<double>& t) { return t ? secs(*t) : "-"; }

void tableRow(std::ostream& o, const ExtremeCaseResult& c, const ExtremeRun& r, const ExtremeEntry& e) {
  const std::string stop = e.failure_kind == Failure::None ? "-" : std::string(failureName(e.failure_kind)) + " " + cell(e.failedAt());
  o << "| " << c.name << " | " << r.setting.label() << " | " << e.method << " | " << outcomeName(e.outcome) << " | " << stop << " | "
    << cell(e.diverged_at) << " | " << sci(e.max_pose) << " | " << sci(e.max_energy) << " | " << sci(e.run_time_s)
    << " | " << e.steps << " | " << (e.eigenfactor ? sci(e.eigen.min_gap) : "") << " | "
    << (e.eigenfactor ? sci(e.eigen.max_abs_Omega) : "") << " | " << (e.eigenfactor ? std::to_string(e.eigen.jacobi_sweeps) : "")
    << " | " << (std::isfinite(e.failure_cond_A) ? sci(e.failure_cond_A) : "") << " |\n";
}

// A mechanism's runs: each method's largest closure gap and the rank it saw, on one line.
void loopsLine(std::ostream& o, const ExtremeRun& r) {
  std::string line;
  for (const ExtremeEntry& e : r.entries) {
    if (!e.has_loops) continue;
    const LoopStats& l = e.loops;
    line += (line.empty() ? "" : ", ") + e.method + " " + sci(l.position_m) + " m / " + sci(l.position_rad) + " rad" +
            (l.rank_max >= 0 ? (l.rank_min == l.rank_max ? " (rank " + std::to_string(l.rank_max) + ")"
                                                         : " (rank " + std::to_string(l.rank_min) + "-" + std::to_string(l.rank_max) + ")")
                             : "");
  }
  if (!line.empty()) o << "  - loops, the largest gap over the steps and samples (in-house: the rank of G A^-1 G^T): " << line << ".\n";
}

void casePart(std::ostream& o, const ExtremeCaseResult& c) {
  o << "\n### " << c.name << "\n\n" << (c.why.empty() ? "(no x-why)" : c.why) << "\n\n";
  o << "`" << c.file << "`: " << c.nu << " speeds; at t = 0 the eigenvalues of A span " << sci(c.lambda_min0) << " to "
    << sci(c.lambda_max0) << ", cond(A) = " << sci(c.cond_A0) << ".\n";
  for (const ExtremeRun& r : c.runs) {
    o << "\n- **" << r.setting.label() << "** (t_end " << gnum(r.t_end) << " s; reference tol " << gnum(r.reference_tol)
      << (r.reference_status == Outcome::Ok ? "" : ", reference FAILED: " + r.reference_failure) << "; horizon at "
      << gnum(kWrongRad) << " rad: " << (r.horizon_wrong ? secs(*r.horizon_wrong) : "beyond t_end") << ").";
    std::string ok;
    for (const ExtremeEntry& e : r.entries)
      if (e.outcome == Outcome::Ok) ok += (ok.empty() ? " " : ", ") + e.method;
    o << (ok.empty() ? " No method was ok." : " ok:" + ok + ".") << "\n";
    for (const ExtremeEntry& e : r.entries) {
      const std::string d = diagnosis(e, c, r);
      if (!d.empty()) o << "  - " << e.method << ": " << d << "\n";
    }
    loopsLine(o, r);
  }
}

}  // namespace

std::string extremeMarkdown(const std::vector<ExtremeCaseResult>& cases, const json& prov) {
  std::ostringstream o;
  o << "# The extreme-case gallery\n\n"
    << "Generated by `" << prov.value("command_line", std::string("eigenmass extreme")) << "` (" << versionText()
    << "; " << prov.value("date_utc", std::string()) << "; " << prov.value("cpu", std::string()) << "). Do not edit: regenerate. Scenes: `data/scenes/extreme/`, each "
    << "with its `x-why`; full reports beside the summary JSON.\n\n"
    << "outcome: ok = completed and within " << gnum(kWrongRad)
    << " rad of the reference up to the reference horizon; wrong = completed but beyond it before the horizon; failed = "
       "stopped (kind and time). pose>1e-3: first time a body's rotation is 1e-3 rad off. dE: |E + W_diss - E(0)| "
       "over the reference's largest kinetic energy. min gap, max |Omega|, sweeps: eigenfactor methods. cond(A) at "
       "stop: at the state where an in-house run stopped.\n\n"
    << "| case | run | method | outcome | stopped | pose>1e-3 | max pose rad | max dE | CPU s | steps | min gap | max "
       "abs Omega | sweeps | cond(A) at stop |\n"
    << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const ExtremeCaseResult& c : cases)
    for (const ExtremeRun& r : c.runs)
      for (const ExtremeEntry& e : r.entries) tableRow(o, c, r, e);
  o << "\n## What happened, case by case\n";
  for (const ExtremeCaseResult& c : cases) casePart(o, c);
  return o.str();
}

namespace {

// What the expected file (a snapshot of an earlier run) says of one method.
struct ExpectedMethod {
  Outcome outcome = Outcome::Ok;
  std::string kind;
  double max_pose = 0;
  std::optional<double> failure_t;
};
struct Expected {
  double t_end = 0;
  std::map<std::string, ExpectedMethod> methods;  // by name
};

// Beyond the outcome and the failure kind, a few numbers are held to the
// snapshot: the max pose error of classical and articulated (the in-house
// methods without eigenfactors: accurate, so a change there is a change of
// the physics or the reference) within a factor 3, and
// every failure time within 10 % (where each method breaks is the gallery's point).
constexpr double kPoseFactor = 3, kFailureTimeRel = 0.1;

// Whether `method` solves A u' = B to round-off at every evaluation: in-house, no eigenfactors.
bool accurateMethod(const std::string& method) {
  Method id;
  return findMethod(method, id) && info(id).engine == Engine::InHouse && !info(id).eigenfactor;
}

std::string numbersDiffer(const ExtremeEntry& e, const ExpectedMethod& m) {
  if (accurateMethod(e.method) && m.max_pose > 1e-12 &&
      !(e.max_pose <= kPoseFactor * m.max_pose && e.max_pose >= m.max_pose / kPoseFactor))
    return "max pose error " + gnum(e.max_pose, 3) + " rad, expected " + gnum(m.max_pose, 3) + " (within " + gnum(kPoseFactor) + "x)";
  if (e.failed() && m.failure_t && std::abs(e.failure_time - *m.failure_t) > kFailureTimeRel * *m.failure_t + 1e-9)
    return "failed at " + gnum(e.failure_time, 4) + " s, expected " + gnum(*m.failure_t, 4) + " s (within 10 %)";
  return "";
}

std::map<std::string, Expected> expectedRuns(const json& expected) {
  std::map<std::string, Expected> out;
  for (const json& c : expected.at("cases"))
    for (const json& r : c.at("runs")) {
      Expected& e = out[c.at("name").get<std::string>() + " " + r.at("setting").get<std::string>()];
      e.t_end = r.at("t_end").get<double>();
      for (const json& m : r.at("methods")) {
        ExpectedMethod& x = e.methods[m.at("name").get<std::string>()];
        const std::string outcome = m.at("outcome").get<std::string>();
        if (!findOutcome(outcome, x.outcome)) throw std::invalid_argument("not an extreme summary (unknown outcome '" + printable(outcome, 40) + "')");
        x.kind = m.at("failure").is_null() ? "none" : m.at("failure").at("kind").get<std::string>();
        x.max_pose = numberFrom(m.at("max_pose_error_rad"));
        if (!m.at("failure").is_null()) x.failure_t = optionalFrom(m.at("failure").at("t"));
      }
    }
  return out;
}

}  // namespace

void validateExpected(const json& expected) {
  try {
    expectedRuns(expected);
  } catch (const json::exception& e) {
    const std::string what = e.what();  // "[json.exception.out_of_range.403] key 'cases' not found"
    const size_t at = what.find("] ");
    throw std::invalid_argument("not an extreme summary (" + (at == std::string::npos ? what : what.substr(at + 2)) + ")");
  }
}

std::vector<std::string> checkExpected(const std::vector<ExtremeCaseResult>& cases, const json& expected) {
  const std::map<std::string, Expected> want = expectedRuns(expected);
  std::vector<std::string> diff;
  for (const ExtremeCaseResult& c : cases)
    for (const ExtremeRun& r : c.runs) {
      const std::string key = c.name + " " + r.setting.key();
      const auto it = want.find(key);
      if (it == want.end()) {
        diff.push_back(key + ": not in the expected file");
        continue;
      }
      if (std::abs(it->second.t_end - r.t_end) > 1e-9 * r.t_end) {
        diff.push_back(key + ": expected file made with t_end " + gnum(it->second.t_end) + ", this run " + gnum(r.t_end));
        continue;
      }
      for (const ExtremeEntry& e : r.entries) {
        const auto m = it->second.methods.find(e.method);
        const std::string kind = failureName(e.failure_kind);
        if (m == it->second.methods.end())
          diff.push_back(key + " " + e.method + ": not in the expected file");
        else if (m->second.outcome != e.outcome || m->second.kind != kind)
          diff.push_back(key + " " + e.method + ": " + outcomeName(e.outcome) + " (" + kind + "), expected " + outcomeName(m->second.outcome) + " (" +
                         m->second.kind + ")");
        else if (const std::string d = numbersDiffer(e, m->second); !d.empty())
          diff.push_back(key + " " + e.method + ": " + d);
      }
    }
  return diff;
}

}  // namespace em
