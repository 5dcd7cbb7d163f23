// A mechanism through the CLI: compare's reference is classical under ida, every
// engine and every tree-only u' is left out in one line, the report and the
// sidecar say how closed the loops stayed, and the loop options are refused
// where they would mean nothing.
#include <filesystem>
#include <fstream>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace {

std::string tempDir() {
  const std::string d = std::string(EM_BINARY_DIR) + "/cli-mechanism-tests";
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace

TEST_CASE("compare on a mechanism: the ida reference, engines left out, the loops in the report", "[cli][mechanism]") {
  const std::string out = tempDir() + "/andrews.json";
  std::remove(out.c_str());
  const Run r = eigenmass("compare " + scene("mechanisms/andrews.json") + " --tol 1e-10 --out " + out, true);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("reference: classical/ida"));
  CHECK_THAT(r.out, Catch::Contains("simbody: not run: no mapping of a mechanism's loops"));
  CHECK_THAT(r.out, Catch::Contains("dart-udot: not run: its u' comes from outside the formation"));
  nlohmann::json report;
  std::ifstream(out) >> report;
  REQUIRE(report["methods"].size() == 7);  // the seven in-house methods
  for (const auto& m : report["methods"]) {
    INFO(m["name"]);
    CHECK(m["status"] == "ok");
    CHECK(m["loops"]["rank"] == 6);  // three balls in the plane: 9 rows, 6 independent
    CHECK(m["loops"]["formulation"] == "projection");
    // The projection holds |g| to its 1e-12 after every step: at the samples, round-off of the 0.1 m mechanism.
    CHECK(m["loops"]["max_position_violation_m"].get<double>() < 1e-12);
    CHECK(m["max_pose_error_rad"].get<double>() < 1e-6);  // against ida at 1e-10 (its own error ~6e-8 rad)
  }
}

TEST_CASE("simulate a mechanism: the loops line and sidecar, loop options on a tree refused", "[cli][mechanism]") {
  const std::string csv = tempDir() + "/andrews.csv";
  std::remove(csv.c_str());
  std::remove((csv + ".json").c_str());
  const Run r = eigenmass("simulate " + scene("mechanisms/andrews.json") + " --integrator rk8pd --tol 1e-12 --formulation baumgarte --out " + csv);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.out, Catch::Contains("loops: largest violation") && Catch::Contains("rank 6"));
  nlohmann::json meta;
  std::ifstream(csv + ".json") >> meta;
  CHECK(meta["loops"]["formulation"] == "baumgarte");
  CHECK(meta["loops"]["baumgarte_alpha"] == 0.0);
  CHECK_FALSE(meta["loops"].contains("projections"));
  const Run ida = eigenmass("simulate " + scene("mechanisms/andrews.json") + " --integrator ida --tol 1e-10 --out " + tempDir() + "/ida.csv --t-end 0.01");
  CHECK(ida.status == 0);
  for (const char* option : {"--formulation baumgarte", "--baumgarte-alpha 5", "--baumgarte-beta 5"}) {
    const Run tree = eigenmass("simulate " + scene("pendulum5.json") + " " + option + " --out " + tempDir() + "/p.csv", true);
    CHECK(tree.status == 2);
    CHECK_THAT(tree.out, Catch::Contains("scene 'pendulum5' has no loops"));
  }
  const Run bad = eigenmass("simulate " + scene("mechanisms/andrews.json") + " --formulation lagrange --out " + tempDir() + "/b.csv", true);
  CHECK(bad.status == 2);
  CHECK_THAT(bad.out, Catch::Contains("--formulation"));
}
