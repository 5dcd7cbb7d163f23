// libFuzzer target (docs/testing.md, Fuzzing): arbitrary bytes through the
// scene loader and, when they load, one formation at the initial state. It
// aborts on a crash or a sanitizer report (the build adds ASan and UBSan), on
// an exception other than the loader's own one-line std::runtime_error, on an
// error message over one line or over 1000 characters, and on a non-finite
// A of a scene the loader accepted and checkInitialState would have to refuse
// by name (that path is exercised, not asserted: it is a documented refusal).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "io/scene.hpp"
#include "solver/formation.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const em::Scene scene = em::loadSceneText(text, "fuzz");
    if (scene.model.n() > 64) return 0;  // keep each input cheap; size is not what is fuzzed here
    em::Workspace ws(scene.model);
    const Eigen::VectorXd q = scene.model.q0(), u = scene.model.u0();
    em::formEquations(scene.model, q.data(), u.data(), ws, true);
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    if (msg.find('\n') != std::string::npos || msg.size() > 1000) {
      std::fprintf(stderr, "error message is not one short line (%zu bytes): %.200s\n", msg.size(), msg.c_str());
      std::abort();
    }
  }
  return 0;
}
