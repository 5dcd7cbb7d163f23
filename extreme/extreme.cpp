#include "extreme/extreme.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "compare/report.hpp"
#include "io/json_input.hpp"
#include "solver/formation.hpp"

namespace em {

using json = nlohmann::json;

std::string ExtremeSetting::key() const { return std::string(integratorName(integrator)) + ":" + gnum(value); }

std::string ExtremeSetting::label() const {
  return std::string(integratorName(integrator)) + (info(integrator).fixed_step ? " dt " : " tol ") + gnum(value);
}

ExtremeSetting parseSetting(const std::string& text) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos) throw std::invalid_argument("'" + printable(text, 40) + "': expected integrator:value (rk4:1e-3)");
  ExtremeSetting s;
  s.integrator = parseIntegrator(text.substr(0, colon));
  if (!info(s.integrator).runs(Engine::InHouse))
    throw std::invalid_argument("'" + text.substr(0, colon) + "' is not an in-house integrator (" +
                                joined(integratorNames(Engine::InHouse)) + ")");
  size_t used = 0;
  const std::string number = text.substr(colon + 1);
  try {
    s.value = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != number.size() || !std::isfinite(s.value) || !(s.value > 0))
    throw std::invalid_argument("'" + printable(text, 40) + "': the step or tolerance must be a finite number > 0");
  return s;
}

std::vector<ExtremeSetting> defaultSettings() {
  // The in-house engine's default fixed step and its reference run (the registry's engine table).
  const RunSpec reference = defaultReferenceSpec(Method::Classical);
  return {{defaultIntegrator(Engine::InHouse), RunSpec().dt}, {reference.integrator, reference.tol}};
}

namespace {

std::vector<std::string> adaptiveInHouseNames() {
  std::vector<std::string> n;
  for (const IntegratorInfo& i : integratorTable())
    if (i.runs(Engine::InHouse) && !i.fixed_step) n.emplace_back(i.name);
  return n;
}

// x-extreme: {"runs": ["rk4:1e-3", ...], "reference_tol": 1e-10, "reference_integrator": "rk8pd"};
// anything else is refused.
void readExtremeKeys(const json& x, ExtremeCase& c) {
  const std::string at = "x-extreme";
  onlyKeys(x, at, {"runs", "reference_tol", "reference_integrator"});
  if (x.contains("reference_integrator")) {
    const std::string path = jsonPath(at, "reference_integrator");
    const std::string name = stringAt(x["reference_integrator"], path);
    Integrator i;
    if (!findIntegrator(name, i) || !info(i).runs(Engine::InHouse) || info(i).fixed_step)
      throw InputError(path, "'" + printable(name, 40) + "' is not an in-house adaptive integrator (" +
                                 joined(adaptiveInHouseNames()) + ")");
    c.reference_integrator = i;
  }
  if (x.contains("runs")) {
    const std::string path = jsonPath(at, "runs");
    const json runs = nonEmptyArrayAt(x["runs"], path);
    c.settings.clear();
    for (size_t i = 0; i < runs.size(); ++i) {
      try {
        c.settings.push_back(parseSetting(stringAt(runs[i], jsonPath(path, i))));
      } catch (const std::invalid_argument& e) {
        throw InputError(jsonPath(path, i), e.what());
      }
    }
  }
  if (x.contains("reference_tol")) c.reference_tol = positiveAt(x["reference_tol"], jsonPath(at, "reference_tol"));
}

void readCaseKeys(const std::string& path, ExtremeCase& c) {
  const json doc = parseJsonStrict(readFile(path, "scene"));
  try {
    if (doc.contains("x-why")) c.why = stringAt(doc["x-why"], "x-why");
    if (doc.contains("x-extreme")) readExtremeKeys(doc["x-extreme"], c);
  } catch (const InputError& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

}  // namespace

ExtremeCase loadExtremeCase(const std::string& path, const UrdfOptions& urdf) {
  ExtremeCase c;
  c.scene = loadScene(path, urdf);
  checkInitialState(c.scene);
  c.path = path;
  c.settings = defaultSettings();
  if (c.scene.source.format != "urdf") readCaseKeys(path, c);
  return c;
}

namespace {

// The first drift diagnostic of an eigenfactor run above kDriftBound.
void firstDrift(const Trajectory& tr, ExtremeEntry& e) {
  for (size_t k = 0; k < tr.diag.size(); ++k) {
    const SampleDiagnostics& d = tr.diag[k];
    const std::pair<const char*, double> moved[] = {
        {"orth_err", d.orth_err}, {"offdiag_rel", d.offdiag_rel}, {"inv_err", d.inv_err}};
    for (const auto& [name, value] : moved)
      if (!(value <= kDriftBound)) {  // NaN counts as moved
        e.first_drift = name;
        e.first_drift_t = tr.t[k];
        return;
      }
  }
}

ExtremeEntry entryOf(const MethodMetrics& m, const Trajectory& tr, const std::vector<double>& thresholds) {
  ExtremeEntry e;
  static_cast<RunEnd&>(e) = m;  // how it ended and its cost, whole
  e.method = m.name();
  e.outcome = m.outcome;
  for (size_t i = 0; i < thresholds.size(); ++i) {
    if (thresholds[i] == kDivergedRad) e.diverged_at = m.divergence_time_s[i];
    if (thresholds[i] == kWrongRad) e.wrong_at = m.divergence_time_s[i];
  }
  e.max_pose = m.pose.value;
  e.max_energy = m.energy.value;
  e.eigenfactor = info(m.run.method).eigenfactor;
  e.eigen = tr.eigen;
  if (e.eigenfactor) firstDrift(tr, e);
  return e;
}

}  // namespace

ExtremeRun summarizeRun(const ComparisonResult& r, const ExtremeSetting& s) {
  ExtremeRun run;
  run.setting = s;
  run.reference_tol = r.reference.run.tol;
  run.t_end = r.t_end;
  run.reference_status = r.reference.status();
  run.reference_failure = r.reference.failure;
  run.horizon_wrong = referenceHorizon(r.reference, r.tight, {kWrongRad})[0];
  for (size_t i = 0; i < r.metrics.size(); ++i) run.entries.push_back(entryOf(r.metrics[i], r.runs[i], r.options.thresholds));
  return run;
}

namespace {

CompareOptions optionsFor(const ExtremeCase& c, const ExtremeSetting& s, const ExtremeOptions& opt) {
  CompareOptions o;
  o.methods = opt.methods;
  o.second_engine = false;  // the gallery compares MuJoCo as a method; its floor would double the cost
  o.sensitivity_twin = false;  // the gallery asks what breaks and when, not how sensitive the reference is (docs/extreme.md)
  o.inhouse.integrator = s.integrator;
  (info(s.integrator).fixed_step ? o.inhouse.dt : o.inhouse.tol) = s.value;
  // A mechanism case: the methods whose engine cannot take it are left out,
  // each said in its report, and the reference is the mechanisms' (classical under ida).
  o.leaveOutRefused(c.scene.model);
  o.useMechanismReference(c.scene.model);
  if (c.reference_tol) o.reference.tol = *c.reference_tol;
  if (c.reference_integrator) {
    o.reference.method = Method::Classical;
    o.reference.integrator = *c.reference_integrator;
  }
  for (RunSpec* spec : o.allSpecs()) spec->options = opt.options;
  o.leaveOutUnrunnable(c.scene.model, false);
  o.grid = opt.grid;
  o.thresholds = {kDivergedRad, kWrongRad};
  return o;
}

void describeScene(const Scene& scene, ExtremeCaseResult& out) {
  const Model& m = scene.model;
  const Workspace ws = equationsAtStart(m);
  const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(ws.A, Eigen::EigenvaluesOnly).eigenvalues();
  out.lambda_min0 = lambda[0];
  out.lambda_max0 = lambda[lambda.size() - 1];
  out.cond_A0 = conditionNumber(ws.A);
  out.nu = m.nu;
}

}  // namespace

void checkExtremeCase(const ExtremeCase& c, const ExtremeOptions& opt) {
  for (const ExtremeSetting& s : c.settings) {
    try {
      checkComparisonOptions(c.scene, optionsFor(c, s, opt));
    } catch (const std::exception& e) {
      throw std::runtime_error(c.path + ": under " + s.key() + ": " + e.what());
    }
  }
}

ExtremeCaseResult runExtremeCase(const ExtremeCase& c, const ExtremeOptions& opt, void (*progress)(const std::string&)) {
  ExtremeCaseResult out;
  out.name = c.scene.model.name;
  out.file = c.path;
  out.why = c.why;
  out.source = c.scene.source;
  describeScene(c.scene, out);
  // One reference for every setting: only the in-house settings differ.
  const ReferenceRuns reference = runReference(c.scene, optionsFor(c, c.settings.front(), opt), progress);
  for (const ExtremeSetting& s : c.settings) {
    if (progress) progress(out.name + " under " + s.label());
    const ComparisonResult r = runComparison(c.scene, optionsFor(c, s, opt), reference, progress);
    ExtremeRun run = summarizeRun(r, s);
    run.report = extremeReportPath(opt.out_dir, c, s);
    writeJsonAtomic(makeReport(r), run.report);
    out.runs.push_back(std::move(run));
  }
  return out;
}

std::string extremeReportPath(const std::string& out_dir, const ExtremeCase& c, const ExtremeSetting& s) {
  const std::string name = c.scene.model.name + "." + integratorName(s.integrator) + "-" + gnum(s.value) + ".report.json";
  return (std::filesystem::path(out_dir) / name).string();
}

}  // namespace em
