#pragma once
// The other engines' methods, schemes and engines by name: their ids are
// given at run time, when engines/table.cpp adds their rows.
#include "engines/engine.hpp"

namespace em::test {

inline Engine engine(const char* name) {
  useEngines();
  return parseEngine(name);
}
inline Method method(const char* name) {
  useEngines();
  return parseMethod(name);
}
inline Integrator scheme(const char* name) {
  useEngines();
  return parseIntegrator(name);
}

}  // namespace em::test
