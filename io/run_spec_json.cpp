#include "io/run_spec_json.hpp"

#include "solver/mechanism/formulation.hpp"

#include "io/json_input.hpp"

namespace em {

void putSetting(nlohmann::json& j, const RunSpec& s) { j[settingKindName(s.settingKind())] = s.setting(); }

nlohmann::json runSpecJson(const RunSpec& s) {
  nlohmann::json j = {{"integrator", integratorName(s.integrator)}};
  putSetting(j, s);
  return j;
}

std::string settingKeyIn(const nlohmann::json& v, const std::string& path, Integrator i) {
  const SettingKind kind = settingKindOf(i);
  const std::string key = settingKindName(kind);
  const std::string other = settingKindName(kind == SettingKind::Dt ? SettingKind::Tolerance : SettingKind::Dt);
  if (v.contains(other)) throw InputError(jsonPath(path, other), std::string(integratorName(i)) + " takes " + key + ", not " + other);
  return key;
}

nlohmann::json loopsJson(const RunEnd& r, const RunSpec& s) {
  if (!r.has_loops) return nullptr;
  const LoopStats& l = r.loops;
  const LoopOptions& o = s.options.loops;
  nlohmann::json j = {{"max_position_violation_m", l.position_m}, {"max_position_violation_rad", l.position_rad},
                      {"max_velocity_violation_m_per_s", l.velocity_m}, {"max_velocity_violation_rad_per_s", l.velocity_rad},
                      {"rank", l.rank_max < 0 ? nlohmann::json(nullptr) : nlohmann::json(l.rank_max)},
                      {"rank_min", l.rank_min < 0 ? nlohmann::json(nullptr) : nlohmann::json(l.rank_min)}};  // null: an engine's run
  if (!l.rank_drop_times.empty()) j["rank_drop_times_s"] = l.rank_drop_times;  // where the multipliers' rank fell (singular positions)
  if (info(s.integrator).dae) {
    j["formulation"] = "ida-ggl-index2";  // the DAE solver's own: no multipliers formulation of ours
    return j;
  }
  if (s.engine() != Engine::InHouse) {
    // The engine closes the loops its own way; the violation is eigenmass's g(q), G u at its samples.
    j["formulation"] = std::string(engineName(s.engine())) + "'s own";
    j["measured_at"] = "the output samples, by eigenmass's g(q) and G u";
    return j;
  }
  j["formulation"] = formulationName(o.formulation);
  j["baumgarte_alpha"] = o.alpha;
  j["baumgarte_beta"] = o.beta;
  j["loop_tol"] = o.loop_tol;
  std::vector<FormulationFigure> figures;  // the formulation's own, from its row
  if (const FormulationInfo& f = formulationRow(o.formulation); f.figures) f.figures(l, o, figures);
  for (const FormulationFigure& f : figures) {
    if (f.list) j[f.key] = *f.list;
    else if (f.integer) j[f.key] = static_cast<long>(f.value);
    else j[f.key] = f.value;
  }
  return j;
}

}  // namespace em
