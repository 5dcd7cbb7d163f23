#pragma once
/// A URDF's text as an engine's own reader is to read it (MuJoCo's, DART's):
/// visual and collision elements removed (meshes need not exist), locked
/// joints made fixed.
#include <string>
#include <vector>

class TiXmlDocument;

namespace em {

/// The text with no visual or collision element and every `locked` joint fixed.
std::string urdfWithoutGeometry(const std::string& text, const std::vector<std::string>& locked);
/// The same edits on a parsed document (its root is <robot>); throws when it has no root.
void removeGeometry(TiXmlDocument& doc, const std::vector<std::string>& locked);

}  // namespace em
