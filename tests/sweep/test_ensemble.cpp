// Ensembles: members perturbed reproducibly as each joint's kind allows, and an
// ensemble plan run through --list and GNU parallel, merged into the
// distributions of divergence times (docs/sweep.md, "ensemble").
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sweep/sweep.hpp"
#include "solver/mechanism/loops.hpp"
#include "support.hpp"

using namespace em;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::string kDir = std::string(EM_BINARY_DIR) + "/ensemble-tests";

int shell(const std::string& cmd) { return WEXITSTATUS(std::system(cmd.c_str())); }

std::vector<std::string> lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::string slurpFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST_CASE("member 0 is the scene, others are drawn reproducibly and stay valid for each joint kind", "[sweep][ensemble]") {
  const Model m = test::loadData("tree_mixed.json");  // every joint kind, ball included
  Ensemble e;
  e.count = 400, e.seed = 5, e.sigma_q = 1e-2, e.sigma_u = 3e-2;
  const Model zero = ensembleMember(m, e, 0);
  CHECK(zero.q0() == m.q0());
  CHECK(zero.u0() == m.u0());
  CHECK(ensembleMember(m, e, 7).q0() == ensembleMember(m, e, 7).q0());  // the same draws, bit for bit
  CHECK(ensembleMember(m, e, 7).q0() != ensembleMember(m, e, 8).q0());
  Ensemble other = e;
  other.seed = 6;
  CHECK(ensembleMember(m, other, 7).u0() != ensembleMember(m, e, 7).u0());
  // Over 399 members x 13 speeds the offsets have mean 0 (within 4 standard errors,
  // sigma / sqrt(n)) and standard deviation sigma_u (within 10 %: its standard error is 2 %).
  double sum = 0, sum2 = 0, n = 0;
  for (int k = 1; k < e.count; ++k) {
    const Model mk = ensembleMember(m, e, k);
    const Eigen::VectorXd du = mk.u0() - m.u0();
    for (int i = 0; i < du.size(); ++i) sum += du[i], sum2 += du[i] * du[i], n += 1;
    for (const Body& b : mk.bodies)
      if (b.joint.type == JointType::Ball) REQUIRE(std::abs(b.joint.q0.norm() - 1) < 1e-15);  // a unit quaternion
  }
  CHECK(std::abs(sum / n) < 4 * e.sigma_u / std::sqrt(n));
  CHECK(std::abs(std::sqrt(sum2 / n) / e.sigma_u - 1) < 0.1);
}

TEST_CASE("quantiles interpolate between order statistics as numpy does", "[sweep][ensemble]") {
  CHECK(*quantile({4, 1, 3, 2}, 0.5) == 2.5);
  CHECK(*quantile({4, 1, 3, 2}, 0.25) == 1.75);  // numpy.quantile([1,2,3,4], 0.25) = 1.75
  CHECK(*quantile({7}, 0.75) == 7);
  CHECK_FALSE(quantile({}, 0.5));
}

TEST_CASE("a member that never crosses is censored: later than t_end in every statistic, here and in Python", "[sweep][ensemble]") {
  const double inf = HUGE_VAL;
  // Sorted 1, 2, 3, inf, inf: the median is the third member's 3 s (over the crossers alone it would be 2 s).
  CHECK(*quantile({3, inf, 1, inf, 2}, 0.5) == 3);
  CHECK(*quantile({3, inf, 1, inf, 2}, 0.25) == 2);
  CHECK(*quantile({3, inf, 1, inf, 2}, 0.75) == inf);  // h = 3: the fourth member, censored, not interpolated
  CHECK(*quantile({1, 2, 3, inf}, 0.5) == 2.5);        // between two crossers: interpolated
  CHECK(*quantile({1, 2, inf, inf}, 0.5) == inf);      // between a crosser and a censored member: censored
  // The median's 95 % interval from the order statistics: n = 10 gives (x_(2), x_(9)), exact coverage
  // 1 - 2 P(B(10, 1/2) <= 1) = 0.9785 (x_(3), x_(8) would cover 0.891 < 0.95).
  const auto ci = medianInterval({10, 9, 8, 7, 6, 5, 4, 3, 2, 1});
  REQUIRE(ci);
  CHECK(ci->first == 2);
  CHECK(ci->second == 9);
  // The same records through eigenmass's CSVs and tools/ensemble_summary.py: 12 members, 7 that cross at
  // scattered times, 5 that never do (the median is a crosser's; q3 and the interval's top are censored).
  std::vector<CaseRecord> records;
  const double times[] = {4.1, 0.7, 9.3, 2.2, 5.5, 3.3, 6.8};
  for (int k = 0; k < 12; ++k) {
    CaseRecord r;
    r.name = "s.m" + std::to_string(k) + ".classical.rk4.0.01";
    r.role = CaseRole::Run, r.scene = "s", r.method = "classical", r.integrator = "rk4", r.member = k, r.setting = 0.01, r.nu = 1;
    r.has_error = true, r.max_coord = 0.5;
    if (k < 7) r.pose_beyond = {times[k], times[k] + 0.5}, r.coord_beyond = {times[k] * 0.9, std::nullopt};
    records.push_back(r);
  }
  const std::vector<EnsembleRow> rows = ensembleRows(records);
  REQUIRE(rows.size() == 4);
  CHECK(rows[0].d.diverged == 7);
  // Sorted: 0.7 2.2 3.3 4.1 5.5 6.8 9.3, then 5 x inf; h = 0.5 x 11 = 5.5: halfway from 6.8 to 9.3.
  CHECK(*rows[0].d.median == Approx(8.05).epsilon(1e-15));
  CHECK(*rows[0].d.q3 == HUGE_VAL);
  const std::string dir = kDir + "-censored";  // in the build tree, not wherever the binary is run from
  fs::create_directories(dir);
  std::ofstream(dir + "/cases.csv") << mergedCsv(records, true);
  std::ofstream(dir + "/ensemble.csv") << ensembleCsv(rows);
  CHECK(shell("/usr/bin/python3 " + test::sourcePath("tools/ensemble_summary.py") + " --check-ensemble " + dir + "/cases.csv " +
              dir + "/ensemble.csv >/dev/null") == 0);
}

TEST_CASE("an ensemble plan through --list and GNU parallel merges into one row per method x setting x metric x threshold",
          "[sweep][ensemble]") {
  json plan = {{"format", "eigenmass-plan/1"},
               {"name", "ens"},
               {"scenes", {test::sourcePath("data/scenes/chain03.json")}},
               {"t_end", 1},
               {"repeats", 1},
               {"ensemble", {{"count", 4}, {"seed", 3}, {"perturb", {{"q", 1e-3}, {"u", 1e-3}}},
                             {"claim", {{"t_s", 0.7}, {"label", "a claimed 0.7 s"}}}}},
               {"reference", {{"method", "classical"}, {"integrator", "rk8pd"}, {"tolerance", 1e-12}}},
               {"reference_check", {{"method", "simbody"}, {"integrator", "rkmerson"}, {"tolerance", 1e-11}}},
               {"lines", {{{"methods", {"classical", "eigen"}}, {"integrator", "rk4"}, {"dt", {1e-2, 5e-3}}}}},
               {"tables", {"runs"}}};
  fs::remove_all(kDir);
  fs::create_directories(kDir);
  const std::string path = kDir + "/ens.json", dir = kDir + "/results";
  std::ofstream(path) << plan.dump(1);
  {  // every run's reference, built directly, is the one the plan lists for its scene and member
    const Plan loaded = loadPlan(path);
    const std::vector<SweepCase> cases = planCases(loaded);
    for (const SweepCase& c : cases) {
      const SweepCase r = referenceCaseOf(loaded, c);
      CHECK(r.name == c.name.substr(0, c.name.find('.', c.name.find(".m") + 1)) + ".reference");
      CHECK(std::count_if(cases.begin(), cases.end(), [&](const SweepCase& x) { return x.name == r.name; }) == 1);
    }
  }
  const std::string exe = std::string(EM_BINARY_DIR) + "/bin/eigenmass";
  REQUIRE(shell(exe + " sweep " + path + " --list --results " + dir + " | parallel --will-cite -j 2 >/dev/null") == 0);
  REQUIRE(shell(exe + " sweep " + path + " --merge " + dir + " >/dev/null") == 0);
  const std::vector<std::string> rows = lines(dir + "/ens-ensemble.csv");
  REQUIRE(!rows.empty());
  CHECK(rows[0] ==
        "scene,method,integrator,setting_kind,setting,metric,threshold,members,diverged,failed,median_s,q1_s,q3_s,min_s,max_s,"
        "median_lo_s,median_hi_s");
  // One convention: tools/ensemble_summary.py recomputes every median, quartile and the median's interval from the
  // per-case CSV (a member that never crossed: later than t_end, +inf) and finds eigenmass's, to round-off.
  CHECK(shell("/usr/bin/python3 " + test::sourcePath("tools/ensemble_summary.py") + " --check-ensemble " + dir + "/ens.csv " +
              dir + "/ens-ensemble.csv >/dev/null") == 0);
  // 2 methods x 2 steps and the reference horizon, x 2 metrics x 2 thresholds.
  CHECK(rows.size() == 1 + (2 * 2 + 1) * 2 * 2);
  for (size_t i = 1; i < rows.size(); ++i) CHECK(rows[i].find(",4,") != std::string::npos);  // members = count
  // Each member's case files record its initial state; member 0's is the scene's.
  const json m0 = json::parse(std::ifstream(dir + "/chain03.m000.reference.json"));
  const json m2 = json::parse(std::ifstream(dir + "/chain03.m002.classical.rk4.0.005.json"));
  const Model scene = test::loadData("chain03.json");
  CHECK(m0.at("member").at("q0").at("link1.q0").get<double>() == scene.q0()[0]);
  CHECK(m2.at("member").at("index") == 2);
  CHECK(m2.at("member").at("q0").at("link1.q0").get<double>() != scene.q0()[0]);
  // The reference records carry the member's Lyapunov exponent, the runs their early error.
  CHECK(m0.at("result").at("lyapunov_per_s").is_number());
  CHECK(m2.at("result").at("pose_error_by_t0_rad").get<double>() >= 0);
  const std::vector<std::string> predicted = lines(dir + "/ens-prediction.csv");
  CHECK(predicted.size() == 1 + 4 * 2 * 2 * 2);  // members x methods x steps x thresholds
  // The case files name the plan's tables and claim: plot draws from them, not from the data's shape.
  CHECK(m2.at("tables") == json::array({"runs"}));
  CHECK(m2.at("claim").at("label") == "a claimed 0.7 s");
  REQUIRE(shell(exe + " plot " + dir + " --format svg --out " + kDir + "/fig >/dev/null") == 0);
  const std::string cdf = slurpFile(kDir + "/fig/ens-cdf.svg"), prediction = slurpFile(kDir + "/fig/ens-prediction.svg");
  CHECK(cdf.find("dotted: a claimed 0.7 s") != std::string::npos);
  CHECK(prediction.find("censored") != std::string::npos);  // members still within 0.1 rad at t_end drawn as such
  CHECK_FALSE(fs::exists(kDir + "/fig/work-precision-chain03.svg"));  // tables: runs (two steps are no work-precision plan)
}

// Issue 73, item 6: members of an ensemble on a mechanism started with their loops open
// (2.5e-4 and 1.4e-3 m on a Watt six-bar) and ran "ok". Each member is now assembled, and its
// case file says by how much; the oracle is the loops' own g(q) at the start, by the run's samples.
TEST_CASE("an ensemble on a mechanism assembles each member's drawn start onto its loops and says by how much", "[sweep][ensemble]") {
  const std::string d = kDir + "_mechanism";
  fs::remove_all(d);
  fs::create_directories(d);
  json plan = {{"format", "eigenmass-plan/1"},
               {"name", "ensm"},
               {"scenes", {test::sourcePath("data/scenes/mechanisms/iftomm_a02_n2.json")}},
               {"t_end", 0.1},
               {"output_dt", 0.05},
               {"repeats", 1},
               {"ensemble", {{"count", 3}, {"seed", 5}, {"perturb", {{"q", 1e-3}, {"u", 1e-3}}}}},
               {"lines", {{{"methods", {"classical"}}, {"integrator", "rk4"}, {"dt", {1e-3}}}}},
               {"tables", {"runs"}}};
  std::ofstream(d + "/ensm.json") << plan.dump(1);
  const std::string exe = std::string(EM_BINARY_DIR) + "/bin/eigenmass";
  REQUIRE(shell(exe + " sweep " + d + "/ensm.json --results " + d + "/results -j 1 >/dev/null 2>&1") == 0);
  for (int k = 1; k < 3; ++k) {
    INFO("member " << k);
    const json c = json::parse(std::ifstream(d + "/results/iftomm_a02_n2.m00" + std::to_string(k) + ".classical.rk4.0.001.json"));
    const json& a = c.at("member").at("assembly");
    // A draw of sigma 1e-3 rad on five coordinates opens the two loops by ~1e-3 m; the assembly closes them.
    CHECK(a.at("gap").get<double>() > 1e-5);
    CHECK(a.at("moved_q").get<double>() > 1e-5);
    CHECK(c.at("result").at("status") == "ok");
    CHECK(c.at("result").at("loops_max_position_m").get<double>() < 1e-9);  // the run's largest violation: closed from the start
    // The recorded start is the assembled one: its loops closed by our g(q) (member q0 by name, in file order).
    const Model m = test::loadData("mechanisms/iftomm_a02_n2.json");
    const std::vector<std::string> names = m.qNames();
    Eigen::VectorXd q(m.nq);
    for (int i = 0; i < m.nq; ++i) {  // internal coordinate i is file coordinate `at`
      Eigen::VectorXd e = Eigen::VectorXd::Zero(m.nq), ef;
      e[i] = 1;
      m.qToFile(e, ef);
      Eigen::Index at;
      ef.maxCoeff(&at);
      q[i] = c.at("member").at("q0").at(names[at]).get<double>();
    }
    CHECK(openLoop(m, q, Eigen::VectorXd::Zero(m.nu), 1e-10).loop < 0);
  }
  const json m0 = json::parse(std::ifstream(d + "/results/iftomm_a02_n2.m000.classical.rk4.0.001.json"));
  CHECK_FALSE(m0.at("member").contains("assembly"));  // member 0 is the scene's own, assembled start
}
