#pragma once
/// A scene ready to run, from whatever file describes it: the model, the run
/// defaults the file states and where it came from. Every error is one line
/// naming the file and the key (docs/scene-format.md).
#include <string>

#include "solver/model.hpp"

namespace em {

struct Scene {
  Model model;
  double t_end = 10.0, output_dt = 0.01;  ///< the file's run defaults (simulate.t_end, .output_dt)
  std::string file;                       ///< where it was read from
};

/// Read, validate and build a scene file. Throws std::runtime_error("file: path: what").
Scene loadScene(const std::string& path);
/// The same from `eigenmass-scene/1` text in memory; `source` names it in errors.
Scene loadSceneText(const std::string& text, const std::string& source);

}  // namespace em
