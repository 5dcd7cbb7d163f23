#pragma once
/// Loader of `eigenmass-scene/1` files (docs/scene-format.md): validation with
/// one-line errors naming the file and the JSON path, then buildModel.
#include <string>

#include "solver/model.hpp"

namespace em {

/// Parse and validate scene text; `source` names it in errors.
/// Throws std::runtime_error("source: path: what") on any defect.
SceneSpec parseSceneSpec(const std::string& text, const std::string& source);
/// Read, validate and build the model of a scene file.
Model loadScene(const std::string& path);
/// The same from text already in memory.
Model loadSceneText(const std::string& text, const std::string& source);

}  // namespace em
