#pragma once
/// Runs one method (in-house or Simbody) on a model: the one place that knows both engines.
#include <string>

#include "solver/integrate.hpp"
#include "solver/model.hpp"

namespace em {

/// What to run: a method name (classical, eigen, eigen-jacobi, eigen-jacobi-orth,
/// simbody), an integrator name and its step or tolerance.
struct RunSpec {
  std::string method = "classical";
  std::string integrator;  ///< empty: rk4 in-house, rkmerson for simbody
  double dt = 1e-3;
  double tol = 1e-10;
  double t_end = 0;        ///< 0: the scene's
  double output_dt = 0;    ///< 0: the scene's
  bool diagnostics = true;
};

/// Known method names, comma-separated, for help texts.
const char* knownMethods();
/// Throws std::invalid_argument naming the known methods unless `name` is one.
void requireKnownMethod(const std::string& name);
/// Throws std::invalid_argument for unknown names or inconsistent options.
Trajectory runMethod(const Model& m, const RunSpec& spec);

/// Equations at the initial state as JSON-ready numbers (file order).
struct Equations {
  int nq = 0, nu = 0;
  Eigen::MatrixXd A;
  Eigen::VectorXd B, udot, eigenvalues;
  double kinetic = 0, potential = 0;
};
Equations inhouseEquations(const Model& m);
Equations simbodyEquations(const Model& m);

}  // namespace em
