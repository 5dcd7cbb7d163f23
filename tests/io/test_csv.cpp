// Trajectory CSV: header layout and an exact round trip.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/csv.hpp"
#include "solver/integrate.hpp"
#include "support.hpp"

using namespace em;

namespace {

// The numbers of every data row, as the file holds them.
std::vector<std::vector<double>> readRows(std::istream& in) {
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<double> v;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) v.push_back(std::stod(c));
    rows.push_back(v);
  }
  return rows;
}

}  // namespace

TEST_CASE("CSV has t coordinates speeds energy and every body pose and round-trips exactly", "[trajectory]") {
  const Model m = test::loadData("tree_mixed.json");
  const Trajectory t = simulate(m, checked(test::runSpec(Method::EigenJacobi, Integrator::RK4, 0.05, 1e-3)));
  const std::string path = std::string(EM_BINARY_DIR) + "/test_trajectory.csv";
  writeCsv(t, path);
  CHECK_FALSE(test::temporaryLeft(path));
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  CHECK(header.rfind("t,hand.q0,hand.q1,torso.q0,", 0) == 0);
  CHECK(header.find(",energy,kinetic,dissipated,hand.x,hand.y,hand.z,hand.qw,hand.qx,hand.qy,hand.qz,torso.x") != std::string::npos);
  CHECK(header.find(",orth_err,offdiag_rel,min_gap,max_Omega,inv_err") != std::string::npos);
  const std::vector<std::string> cols = csvColumns(t);
  std::string expected;
  for (size_t i = 0; i < cols.size(); ++i) expected += (i ? "," : "") + cols[i];
  CHECK(header == expected);
  const auto rows = readRows(in);
  REQUIRE(rows.size() == t.size());
  const int nq = m.nq, nu = m.nu, e = 1 + nq + nu;
  for (size_t k = 0; k < t.size(); ++k) {  // 17 significant digits: exact
    CHECK(rows[k][0] == t.t[k]);
    CHECK(Eigen::Map<const Eigen::VectorXd>(rows[k].data() + 1, nq) == t.q[k]);
    CHECK(Eigen::Map<const Eigen::VectorXd>(rows[k].data() + 1 + nq, nu) == t.u[k]);
    CHECK(rows[k][e] == t.energy[k]);
    CHECK(rows[k][e + 1] == t.kinetic[k]);
    CHECK(rows[k][e + 2] == t.dissipated[k]);
  }
  const double* pose3 = rows.back().data() + e + 3 + 7 * 3;
  CHECK(Vec4(pose3[3], pose3[4], pose3[5], pose3[6]) == t.poses.back()[3].quat);
}

TEST_CASE("the sampler stores the source's order: the first sample is the file's initial state", "[trajectory]") {
  const Model m = test::loadData("tree_mixed.json");
  const Trajectory t = simulate(m, checked(test::runSpec(Method::Classical, Integrator::RK4, 0.01, 1e-3)));
  Eigen::VectorXd qf, uf;
  m.qToFile(m.q0(), qf);
  m.uToFile(m.u0(), uf);
  CHECK(t.q.front() == qf);
  CHECK(t.u.front() == uf);
  CHECK(t.q_names == m.qNames());
  CHECK(t.run.method == Method::Classical);
}
