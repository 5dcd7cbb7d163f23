#pragma once
/// How a result was produced: command line, eigenmass version and git commit,
/// library versions, compiler and flags, machine, date. Every report and
/// every trajectory sidecar carries it (docs/report-format.md, Provenance).
#include <string>

#include <nlohmann/json.hpp>

#include "io/scene.hpp"

namespace em {

/// Remember the command line (main calls it first).
void setCommandLine(int argc, char** argv);

/// The provenance block, as of now.
nlohmann::json provenance();

/// Where the scene came from: {file, format, sha256, import_notes}.
nlohmann::json sceneSourceJson(const SceneSource& s);

/// "eigenmass 0.3.0 (commit abc1234)" and the libraries: `eigenmass --version`.
std::string versionText();

}  // namespace em
