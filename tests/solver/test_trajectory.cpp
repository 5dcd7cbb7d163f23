// Trajectory CSV: header layout and an exact round trip.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "solver/integrate.hpp"
#include "support.hpp"

using namespace em;

TEST_CASE("CSV has t coordinates speeds energy and every body pose and round-trips exactly", "[trajectory]") {
  const Model m = test::loadData("tree_mixed.json");
  SimOptions o;
  o.t_end = 0.05;
  const Trajectory t = simulate(m, Method::EigenJacobi, o);
  const std::string path = std::string(EM_BINARY_DIR) + "/test_trajectory.csv";
  writeCsv(t, path);
  CHECK_FALSE(std::filesystem::exists(path + ".tmp"));
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  CHECK(header.rfind("t,hand.q0,hand.q1,torso.q0,", 0) == 0);
  CHECK(header.find(",energy,kinetic,hand.x,hand.y,hand.z,hand.qw,hand.qx,hand.qy,hand.qz,torso.x") != std::string::npos);
  CHECK(header.find(",orth_err,offdiag_rel,min_gap,max_Omega,inv_err") != std::string::npos);
  const Trajectory r = readCsv(path);
  CHECK(r.q_names == t.q_names);
  CHECK(r.u_names == t.u_names);
  CHECK(r.body_names == t.body_names);
  REQUIRE(r.size() == t.size());
  CHECK(r.t == t.t);
  CHECK(r.q == t.q);  // 17 significant digits: exact
  CHECK(r.energy == t.energy);
  CHECK(r.kinetic == t.kinetic);
  CHECK(r.poses.back()[3].quat == t.poses.back()[3].quat);
}
