#include <algorithm>
#include <mutex>
#include <stdexcept>

#include "reference/engine.hpp"

namespace em {

// Each engine's row, defined in its own file (reference/<name>.cpp).
EngineRow simbodyEngine();
EngineRow mujocoEngine();
EngineRow dartEngine();
EngineRow bulletEngine();
EngineRow odeEngine();

const std::vector<EngineRow>& engineRows() {
  static const std::vector<EngineRow> rows = {simbodyEngine(), mujocoEngine(), dartEngine(), bulletEngine(), odeEngine()};
  return rows;
}

namespace {

// An engine's u' under the in-house integrators, as a method of the in-house engine.
void addUdotMethod(const EngineUdotMethod& u, const char* engine) {
  MethodInfo m;
  m.dynamics_of = engine;
  m.name = u.name;
  m.make = u.make;
  m.summary = u.summary;
  m.colour = u.colour;
  m.tree_only = true;
  addMethod(m);
}

}  // namespace

void useEngines() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const EngineRow& r : engineRows()) {
      EngineInfo info = r.info;
      info.code = &r.code;  // the row's own code, found by the id addEngine gives
      addEngine(info);
      if (r.code.udot_method.name) addUdotMethod(r.code.udot_method, r.info.name);
    }
  });
}

const EngineCode& engineCode(Engine e) {
  useEngines();
  const EngineInfo& row = info(e);
  if (!row.code) throw std::logic_error(std::string("engineCode: '") + row.name + "' runs no code of reference/");
  return *row.code;
}

namespace {

// The tables hold every engine before any program reads them: this unit is
// linked wherever an engine can run (engineCode is the one dispatch point).
const bool registered = (useEngines(), true);

}  // namespace

std::string jointsOfKinds(const Model& m, const std::vector<JointType>& kinds) {
  std::string out;
  for (JointType k : kinds) {
    const auto b = std::find_if(m.bodies.begin(), m.bodies.end(), [k](const Body& b) { return b.joint.type == k; });
    if (b != m.bodies.end()) out += (out.empty() ? "" : ", ") + std::string(jointTypeName(k)) + " (body '" + b->name + "')";
  }
  return out;
}

std::string unmappedLoop(const Model& m, const std::vector<LoopType>& mapped, const std::string& constraints) {
  for (const Loop& l : m.loops) {
    if (std::find(mapped.begin(), mapped.end(), l.type) != mapped.end()) continue;
    std::string kinds;
    for (LoopType k : mapped) kinds += (kinds.empty() ? "" : ", ") + std::string(loopRow(k).name);
    return "loop '" + l.name + "' is a " + loopRow(l.type).name + " closure, which " + constraints + " cannot express (it maps " +
           kinds + ")";
  }
  return "";
}

}  // namespace em
