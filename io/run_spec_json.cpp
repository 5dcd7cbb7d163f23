#include "io/run_spec_json.hpp"

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

}  // namespace em
