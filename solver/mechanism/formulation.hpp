#pragma once
/// The formulations that keep a mechanism's loops closed (docs/theory.md §15):
/// one row each, named as --formulation names them.
#include <string>
#include <vector>

#include "solver/method_options.hpp"

namespace em {

/// One row per formulation (solver/method_options.hpp's Formulation): its
/// name (--formulation) and what it does.
struct FormulationInfo {
  Formulation id;
  const char* name;
  const char* summary;
};
const std::vector<FormulationInfo>& formulationTable();
const char* formulationName(Formulation f);
/// The formulation named `name`, or false.
bool findFormulation(const std::string& name, Formulation& out);

}  // namespace em
