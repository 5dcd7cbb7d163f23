#pragma once
/// The `eigenmass-scene/1` format (docs/scene-format.md): the scene as written
/// (parents by name, file order), its validation with one-line errors naming
/// the JSON path, and the model it describes.
#include <string>
#include <vector>

#include "solver/model.hpp"

namespace em {

/// A body as written in a scene: parent by name ("ground" or a body), file order.
struct BodySpec {
  std::string name, parent;
  double mass = 1.0;
  Mat3 inertia = Mat3::Identity();  ///< about the CM, body frame (matrix entries)
  Joint joint;
};

/// A scene as written: bodies in file order and the run defaults.
struct SceneSpec {
  std::string name;
  Vec3 gravity{0, 0, -9.81};
  std::vector<BodySpec> bodies;
  double t_end = 10.0, output_dt = 0.01;  ///< simulate.t_end, simulate.output_dt
};

/// Parse and validate scene text. Throws InputError (JSON path: what) on any defect.
SceneSpec parseSceneSpec(const std::string& text);

/// The model of a scene as written: parents resolved by name, then the
/// solver's buildModel. Throws InputError naming `bodies[i].name` or
/// `bodies[i].parent` (file indices).
Model buildModel(const SceneSpec& spec);

}  // namespace em
