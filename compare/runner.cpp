#include "compare/runner.hpp"

#include <stdexcept>

#include "reference/simbody_reference.hpp"
#include "solver/formation.hpp"

namespace em {

const char* knownMethods() { return "classical, eigen, eigen-jacobi, eigen-jacobi-orth, simbody"; }

void requireKnownMethod(const std::string& name) {
  Method dummy;
  if (name != "simbody" && !parseMethod(name, dummy))
    throw std::invalid_argument("unknown method '" + name + "' (" + knownMethods() + ")");
}

Trajectory runMethod(const Model& m, const RunSpec& spec) {
  requireKnownMethod(spec.method);
  const double t_end = spec.t_end > 0 ? spec.t_end : m.t_end;
  const double output_dt = spec.output_dt > 0 ? spec.output_dt : m.output_dt;
  if (spec.method == "simbody") {
    if (!(spec.tol > 0)) throw std::invalid_argument("--tol must be > 0");
    return SimbodyReference(m).simulate(spec.integrator.empty() ? "rkmerson" : spec.integrator, spec.tol, t_end,
                                        output_dt);
  }
  Method method;
  parseMethod(spec.method, method);
  SimOptions opt;
  if (!spec.integrator.empty() && !parseIntegrator(spec.integrator, opt.integrator))
    throw std::invalid_argument("unknown integrator '" + spec.integrator + "' (rk4, rkf45, rk8pd, bsimp)");
  opt.dt = spec.dt;
  opt.tol = spec.tol;
  opt.t_end = t_end;
  opt.output_dt = output_dt;
  opt.diagnostics = spec.diagnostics;
  return simulate(m, method, opt);
}

namespace {

// Reorder internal-order results to the file's order and add eigenvalues.
Equations toFileOrder(const Model& m, const Eigen::MatrixXd& A, const Eigen::VectorXd& B, const Eigen::VectorXd& udot,
                      double kinetic, double potential) {
  const std::vector<int> p = m.uFilePermutation();
  Equations e;
  e.nq = m.nq;
  e.nu = m.nu;
  e.A.resize(m.nu, m.nu);
  e.B.resize(m.nu);
  e.udot.resize(m.nu);
  for (int i = 0; i < m.nu; ++i) {
    e.B[i] = B[p[i]];
    e.udot[i] = udot[p[i]];
    for (int j = 0; j < m.nu; ++j) e.A(i, j) = A(p[i], p[j]);
  }
  e.eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(e.A, Eigen::EigenvaluesOnly).eigenvalues();
  e.kinetic = kinetic;
  e.potential = potential;
  return e;
}

}  // namespace

Equations inhouseEquations(const Model& m) {
  Workspace ws(m);
  const Eigen::VectorXd q = m.q0(), u = m.u0();
  formEquations(m, q.data(), u.data(), ws);
  const Eigen::LLT<Eigen::MatrixXd> llt(ws.A);
  if (llt.info() != Eigen::Success) throw std::runtime_error("mass matrix A is not positive definite at the initial state");
  return toFileOrder(m, ws.A, ws.B, llt.solve(ws.B), ws.kinetic, ws.potential);
}

Equations simbodyEquations(const Model& m) {
  SimbodyReference ref(m);
  const Eigen::MatrixXd A = ref.massMatrix();
  const Eigen::VectorXd B = ref.rhs(), udot = ref.udot();
  return toFileOrder(m, A, B, udot, ref.kineticEnergy(), ref.potentialEnergy());
}

}  // namespace em
