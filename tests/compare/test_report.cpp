// The report: documented schema, round trip through a file, failed methods,
// decimated series, atomic writing.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "compare/report.hpp"
#include "engines.hpp"
#include "support.hpp"
#include "synthetic.hpp"

using namespace em;
using json = nlohmann::json;

namespace {

ComparisonResult synthetic() {
  CompareOptions o;
  o.methods = {Method::Classical, Method::Eigen};
  Trajectory failed = test::turning(Method::Eigen, 0.021, 0.5, 3.0);
  markFailed(failed, 3.0, Failure::NonPositiveEigenvalue, "eigenvalue lambda_0 = -0.1 <= 0");
  failed.failure_cond_A = 250.0;
  ComparisonResult r = compareTrajectories(test::turning(em::test::method("simbody"), 0, 0), test::turning(em::test::method("simbody"), 1e-6, 0),
                                   {test::turning(Method::Classical, 1e-5, 0), failed}, o);
  r.scene_name = "synthetic";
  r.t_end = 10;
  r.output_dt = 0.01;
  return r;
}

}  // namespace

TEST_CASE("the report has the documented top level and method fields", "[report]") {
  const json j = makeReport(synthetic());
  CHECK(j["format"] == "eigenmass-report/1");
  for (const char* k : {"scene", "options", "reference", "methods", "series", "gate", "provenance"}) CHECK(j.contains(k));
  CHECK(j["provenance"]["eigenmass_version"].is_string());
  CHECK(j["gate"].is_null());
  for (const char* k : {"engine", "integrator", "tolerance", "horizon_s"}) CHECK(j["reference"].contains(k));
  REQUIRE(j["methods"].size() == 2);
  const json& c = j["methods"][0];
  for (const char* k : {"name", "integrator", "status", "failure", "run_time_s", "steps", "rhs_evals",
                        "max_pose_error_rad", "max_position_error_m", "divergence_time_s", "energy_error_max",
                        "energy_error_final", "diagnostics"})
    CHECK(c.contains(k));
  CHECK(c["dt"] == 1e-3);
  CHECK(c["divergence_time_s"]["1e-3"].is_null());
  CHECK(c["max_pose_error_rad"].get<double>() == Approx(1e-4).epsilon(1e-9));
}

TEST_CASE("threshold keys hold no dot and read back exactly", "[report]") {
  // pandas.json_normalize joins nested keys with '.': a key "0.001" would be
  // split by whoever reads the column name back.
  CHECK(thresholdKey(1e-3) == "1e-3");
  CHECK(thresholdKey(0.1) == "1e-1");
  CHECK(thresholdKey(1.0) == "1e0");
  CHECK(thresholdKey(2.5e-3) == "2p5e-3");
  CHECK(thresholdKey(12.0) == "1p2e1");
  for (double th : {1e-3, 0.1, 2.5e-3, 1.0 / 3.0, 7e-300, 0.3}) {
    std::string k = thresholdKey(th);
    CHECK(k.find('.') == std::string::npos);
    std::replace(k.begin(), k.end(), 'p', '.');
    CHECK(std::strtod(k.c_str(), nullptr) == th);
  }
}

TEST_CASE("a failed method appears with its time and cause", "[report]") {
  const json j = makeReport(synthetic());
  const json& e = j["methods"][1];
  CHECK(e["status"] == "failed");
  CHECK(e["outcome"] == "failed");
  CHECK(j["methods"][0]["outcome"].is_string());
  CHECK(e["failure"]["t"] == 3.0);
  CHECK(e["failure"]["cause"] == "eigenvalue lambda_0 = -0.1 <= 0");
  CHECK(e["failure"]["kind"] == "eigenvalue-nonpositive");
  CHECK(e["failure"]["cond_A"] == 250.0);
  CHECK(j["methods"][0]["failure"].is_null());
  CHECK(e["divergence_time_s"]["1e-1"] == 3.0);
  CHECK(e["divergence_time_s"]["1e-3"].get<double>() == Approx(0.05));
}

TEST_CASE("series are decimated to at most the asked number of points", "[report]") {
  const json j = makeReport(synthetic(), nullptr, 100);
  const size_t n = j["series"]["t"].size();
  CHECK(n <= 101);  // stride 11 over 1001 samples, plus the last
  CHECK(n >= 90);
  CHECK(j["series"]["t"].back() == 10.0);
  CHECK(j["series"]["methods"]["classical"]["pose_error_rad"].size() == n);
  CHECK(j["series"]["methods"]["eigen"]["pose_error_rad"].size() < n);  // stopped at 3 s
}

TEST_CASE("the figures' series: the reference check and the angle that leaves first, of every run", "[report]") {
  // The synthetic reference's tighter twin turns 1e-6 rad/s faster (synthetic.hpp): its
  // pose error is 1e-6 t exactly; the eigen run turns 0.021 rad/s faster and stops at 3 s.
  const json j = makeReport(synthetic());
  const json& check = j["series"]["reference_check"]["pose_error_rad"];
  REQUIRE(check.size() == j["series"]["t"].size());
  CHECK(check.back().get<double>() == Approx(1e-5).epsilon(1e-6));
  const json& c = j["series"]["coordinate"];
  CHECK(c["name"] == "body.q0");
  const size_t k = 100 / j["series"]["stride"].get<size_t>();  // the sample at t = 1 s
  REQUIRE(j["series"]["t"][k].get<double>() == Approx(1.0));
  CHECK(c["reference"][k].get<double>() == Approx(0.3));
  CHECK(c["methods"]["eigen"][k].get<double>() == Approx(0.321));
  CHECK(c["methods"]["eigen"].size() == j["series"]["methods"]["eigen"]["pose_error_rad"].size());
}

TEST_CASE("the figure's coordinate is the angle a method leaves the reference on first", "[report]") {
  // A second angle, constant in the reference, drifting at 0.2 rad/s in the run:
  // it leaves by 0.1 rad at 0.5 s while the first angle stays within 1e-4.
  const auto withSecond = [](Trajectory tr, double rate) {
    tr.q_names = {"a.q0", "b.q0"};
    tr.angle_coords = {0, 1};
    for (size_t k = 0; k < tr.q.size(); ++k) tr.q[k] = Eigen::Vector2d(tr.q[k][0], 0.5 + rate * tr.t[k]);
    return tr;
  };
  CompareOptions o;
  o.methods = {Method::Classical};
  const ComparisonResult r = compareTrajectories(withSecond(test::turning(em::test::method("simbody"), 0, 0), 0),
                                         withSecond(test::turning(em::test::method("simbody"), 1e-6, 0), 0),
                                         {withSecond(test::turning(Method::Classical, 1e-5, 0), 0.2)}, o);
  const json c = makeReport(r)["series"]["coordinate"];
  CHECK(c["name"] == "b.q0");
  CHECK(c["index"] == 1);
  const ComparisonResult still = compareTrajectories(withSecond(test::turning(em::test::method("simbody"), 0, 0), 0),
                                             withSecond(test::turning(em::test::method("simbody"), 1e-6, 0), 0),
                                             {withSecond(test::turning(Method::Classical, 1e-5, 0), 0)}, o);
  CHECK(makeReport(still)["series"]["coordinate"]["name"] == "a.q0");  // none leaves: the first angle
}

TEST_CASE("a report round-trips through its file and no temporary is left", "[report]") {
  const std::string path = std::string(EM_BINARY_DIR) + "/test_report.json";
  const json j = makeReport(synthetic());
  writeJsonAtomic(j, path);
  CHECK_FALSE(test::temporaryLeft(path));
  std::ifstream in(path);
  CHECK(json::parse(in) == j);
  CHECK_THROWS_WITH(writeJsonAtomic(j, "/nonexistent-dir/r.json"), Catch::Contains("/nonexistent-dir/r.json"));
}
