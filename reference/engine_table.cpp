#include <mutex>
#include <stdexcept>

#include "reference/engine.hpp"

namespace em {

// Each engine's row, defined in its own file (reference/<engine>_*.cpp).
EngineRow simbodyEngine();
EngineRow mujocoEngine();
EngineRow dartEngine();
EngineRow bulletEngine();
EngineRow odeEngine();

const std::vector<EngineRow>& engineRows() {
  static const std::vector<EngineRow> rows = {simbodyEngine(), mujocoEngine(), dartEngine(), bulletEngine(), odeEngine()};
  return rows;
}

void useEngines() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (const EngineRow& r : engineRows()) {
      addEngine(r.name, r.summary, r.schemes, r.fixed_default, r.adaptive_default, r.max_tol, r.colour);
      if (const EngineUdotMethod& u = r.udot_method; u.name)
        addMethod({Method::Classical, u.name, Engine::InHouse, Correction::None, ExtraState::None, false, u.make, {},
                   u.summary, u.colour});
    }
  });
}

const EngineRow& engineRow(Engine e) {
  useEngines();
  const std::string name = engineName(e);
  for (const EngineRow& r : engineRows())
    if (name == r.name) return r;
  throw std::logic_error("engineRow: '" + name + "' has no row of reference/engine_table.cpp");
}

namespace {

// The tables hold every engine before any program reads them: this unit is
// linked wherever an engine can run (engineRow is the one dispatch point).
const bool registered = (useEngines(), true);

}  // namespace

}  // namespace em
