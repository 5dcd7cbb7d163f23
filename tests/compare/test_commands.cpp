// The CLI as a user runs it: exit codes, one-line errors, JSON and CSV outputs.
#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "support.hpp"

namespace {

struct Run {
  int status;
  std::string out;
};

// Run the built eigenmass with arguments; stdout (and stderr if asked) captured.
Run eigenmass(const std::string& args, bool with_stderr = false) {
  const std::string cmd = std::string(EM_BINARY_DIR) + "/bin/eigenmass " + args + (with_stderr ? " 2>&1" : " 2>/dev/null");
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
  const int st = pclose(p);
  return {WEXITSTATUS(st), out};
}

std::string scene(const std::string& name) { return em::test::sourcePath("data/scenes/" + name); }

}  // namespace

TEST_CASE("equations prints A B udot energy and eigenvalues and the simbody engine agrees", "[cli][crosscheck]") {
  const Run a = eigenmass("equations " + scene("pendulum5.json"));
  const Run b = eigenmass("equations " + scene("pendulum5.json") + " --engine simbody");
  REQUIRE(a.status == 0);
  REQUIRE(b.status == 0);
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  CHECK(ja["nq"] == 7);
  CHECK(ja["nu"] == 7);
  CHECK(ja["A"].size() == 7);
  CHECK(ja["A"][0].size() == 7);
  CHECK(ja["energy"]["total"].get<double>() == Approx(-96.927410600287).epsilon(1e-13));
  double amax = 0, diff = 0;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j) {
      amax = std::max(amax, std::abs(jb["A"][i][j].get<double>()));
      diff = std::max(diff, std::abs(ja["A"][i][j].get<double>() - jb["A"][i][j].get<double>()));
    }
  CHECK(diff <= 1e-12 * amax);
  for (int i = 0; i < 7; ++i)
    CHECK(ja["eigenvalues"][i].get<double>() == Approx(jb["eigenvalues"][i].get<double>()).epsilon(1e-12));
}

TEST_CASE("a malformed scene is one line on stderr and exit status 2", "[cli][scene]") {
  const std::string bad = em::test::sourcePath("tests/scenes/malformed/zero_axis.json");
  const Run r = eigenmass("equations " + bad, true);
  CHECK(r.status == 2);
  CHECK(r.out == "eigenmass: error: " + bad + ": bodies[1].joint.axis: zero axis\n");
}

TEST_CASE("simulate writes the CSV it names and reports the energy drift", "[cli]") {
  const std::string out = std::string(EM_BINARY_DIR) + "/cli_sim/chain02.csv";
  std::filesystem::remove_all(std::string(EM_BINARY_DIR) + "/cli_sim");
  const Run r = eigenmass("simulate " + scene("chain02.json") + " --method eigen-jacobi --t-end 0.2 --out " + out);
  CHECK(r.status == 0);
  CHECK(r.out.find("status ok") != std::string::npos);
  CHECK(r.out.find("max |E(t) - E(0)|") != std::string::npos);
  std::ifstream in(out);
  std::string header;
  std::getline(in, header);
  CHECK(header.rfind("t,link1.q0,link1.q1,link1.q2,link2.q0,link1.u0", 0) == 0);
  int rows = 0;
  for (std::string line; std::getline(in, line);) ++rows;
  CHECK(rows == 21);
}

TEST_CASE("bad options are one-line errors - --help documents defaults", "[cli]") {
  const Run r = eigenmass("simulate " + scene("chain02.json") + " --dt 0.003 --t-end 1", true);
  CHECK(r.status == 2);
  CHECK(r.out.find("output_dt must be a whole multiple of dt") != std::string::npos);
  const Run h = eigenmass("simulate --help");
  CHECK(h.status == 0);
  CHECK(h.out.find("--dt") != std::string::npos);
  CHECK(h.out.find("0.001") != std::string::npos);
}
