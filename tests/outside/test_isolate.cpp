// outside/isolate.cpp: work in a child process; its text back, or its crash, hang or exception named.
#include <unistd.h>

#include <csignal>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "outside/isolate.hpp"

using namespace em;

TEST_CASE("isolation returns the child's text, bit for bit", "[outside]") {
  std::string big(1 << 20, 'x');  // larger than a pipe's buffer: the parent reads while the child writes
  big[12345] = '\0';
  const Isolated r = runIsolated([&] { return big; }, 5);
  REQUIRE(r.ok);
  CHECK(r.output == big);
}

TEST_CASE("isolation names a crash, a hang and an exception, with the last beat", "[outside]") {
  const Isolated crash = runIsolated([]() -> std::string {
    isolatedBeat(0.5);
    std::raise(SIGSEGV);
    return "";
  }, 5);
  CHECK_FALSE(crash.ok);
  CHECK(crash.failure == "crashed (SIGSEGV)");
  CHECK(crash.beat);
  CHECK(crash.t == 0.5);
  const Isolated hang = runIsolated([]() -> std::string {
    isolatedBeat(0.25);
    for (volatile int spin = 1; spin;) {
    }
    return "";
  }, 0.5);
  CHECK_FALSE(hang.ok);
  CHECK(hang.failure == "no return within 0.5 s (killed)");
  CHECK(hang.t == 0.25);
  const Isolated thrown = runIsolated([]() -> std::string { throw std::runtime_error("bad model"); }, 5);
  CHECK_FALSE(thrown.ok);
  CHECK(thrown.failure == "bad model");
  CHECK_FALSE(thrown.beat);
}

TEST_CASE("a child that keeps beating is not killed however long it runs", "[outside]") {
  const Isolated r = runIsolated([] {
    for (int k = 0; k < 30; ++k) {  // 0.6 s of work, 20 ms between beats, against a 0.2-s timeout
      isolatedBeat(k);
      usleep(20000);
    }
    return std::string("done");
  }, 0.2);
  CHECK(r.ok);
  CHECK(r.output == "done");
}
