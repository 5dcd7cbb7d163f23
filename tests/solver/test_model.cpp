// Tier 1 (closed form): topology, renumbering and the structure matrix T.
#include <catch2/catch.hpp>

#include "support.hpp"

using namespace em;

namespace {
std::vector<std::string> internalNames(const Model& m) {
  std::vector<std::string> n;
  for (const Body& b : m.bodies) n.push_back(b.name);
  return n;
}
}  // namespace

TEST_CASE("a branched tree listed children-first is renumbered parents-first", "[closedform][model]") {
  const Model m = test::loadData("tree_mixed.json");
  // Depth-first from the root, children in file order.
  CHECK(internalNames(m) ==
        std::vector<std::string>{"torso", "upperarm", "forearm", "hand", "thigh", "shin", "foot"});
  for (int i = 0; i < m.n(); ++i) CHECK(m.bodies[i].parent < i);
  // T(j,i) = 1 when j is i or an ancestor of i (docs/theory.md §2): written out by hand.
  Eigen::MatrixXi T(7, 7);
  T << 1, 1, 1, 1, 1, 1, 1,  // torso is everyone's ancestor
      0, 1, 1, 1, 0, 0, 0,   // upperarm: forearm, hand
      0, 0, 1, 1, 0, 0, 0,   // forearm: hand
      0, 0, 0, 1, 0, 0, 0,   //
      0, 0, 0, 0, 1, 1, 1,   // thigh: shin, foot
      0, 0, 0, 0, 0, 1, 1,   // shin: foot
      0, 0, 0, 0, 0, 0, 1;
  CHECK(m.T == T);
  CHECK(m.nq == 2 + 4 + 1 + 3 + 2 + 1 + 4);
  CHECK(m.nu == 2 + 3 + 1 + 3 + 2 + 1 + 3);
}

TEST_CASE("a forest has one block of T per tree and no coupling between trees", "[closedform][model]") {
  const Model m = test::loadData("forest.json");
  CHECK(internalNames(m) == std::vector<std::string>{"a1", "a2", "a3", "a2b", "b1", "b2", "c1"});
  Eigen::MatrixXi T(7, 7);
  T << 1, 1, 1, 1, 0, 0, 0,  //
      0, 1, 1, 0, 0, 0, 0,   //
      0, 0, 1, 0, 0, 0, 0,   //
      0, 0, 0, 1, 0, 0, 0,   //
      0, 0, 0, 0, 1, 1, 0,   //
      0, 0, 0, 0, 0, 1, 0,   //
      0, 0, 0, 0, 0, 0, 1;
  CHECK(m.T == T);
}

TEST_CASE("outputs follow the files order whatever the internal order", "[closedform][model]") {
  const Model m = test::loadData("tree_mixed.json");
  const auto qn = m.qNames();
  CHECK(qn.front() == "hand.q0");
  CHECK(qn[2] == "torso.q0");
  CHECK(qn.back() == "foot.q3");
  // The file-order round trip is the identity, and internal order differs.
  Eigen::VectorXd qf = Eigen::VectorXd::LinSpaced(m.nq, 0, m.nq - 1), q, back;
  q.resize(m.nq);  // file order -> internal order through the permutation
  const std::vector<int> p = m.qFilePermutation();
  for (int k = 0; k < m.nq; ++k) q[p[k]] = qf[k];
  m.qToFile(q, back);
  CHECK(back == qf);
  CHECK(q != qf);
}

TEST_CASE("buildModel rejects topology errors with the files body index", "[closedform][model]") {
  SceneSpec s = test::chainSpec(3);
  s.bodies[2].parent = "link3";
  CHECK_THROWS_WITH(buildModel(s), Catch::Contains("bodies[2].parent") && Catch::Contains("own parent"));
  s = test::chainSpec(3);
  s.bodies[0].parent = "link3";  // link1 -> link3 -> link2 -> link1
  CHECK_THROWS_WITH(buildModel(s), Catch::Contains("bodies[0].parent: cycle"));
}
