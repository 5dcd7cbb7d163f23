#pragma once
/// Strict JSON input that knows where it is: a parse callback tracks the JSON
/// path of the value being read, so that parser-level failures (a number too
/// large for a double, 1e999) and duplicate keys (which nlohmann would
/// silently resolve to the last) name their key. Scenes, tolerance files and
/// plans are read through it.
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace em {

/// A defect of an input file at a JSON path ("bodies[1].mass: must be > 0").
struct InputError : std::runtime_error {
  InputError(const std::string& path, const std::string& what) : std::runtime_error(path + ": " + what), path(path) {}
  std::string path;
};

/// Parse `text` strictly. Throws InputError: "(document)" with line and column
/// for a syntax error, the path for a duplicate key or an overflowing number.
nlohmann::json parseJsonStrict(const std::string& text);

/// Largest input file read (scene, URDF, plan, tolerances, summary): 256 MiB.
inline constexpr size_t kMaxInputBytes = size_t(256) << 20;
/// The whole content of a file; throws std::runtime_error("path: cannot open
/// ...", "is a folder", "larger than 256 MiB") in one line.
std::string readFile(const std::string& path, const std::string& what);

/// readFile, then parseJsonStrict; a syntax error names the file:
/// "x.report.json: (document): invalid JSON at line 3, column 1".
nlohmann::json readJsonFile(const std::string& path, const std::string& what);

/// `text` safe for a one-line message: control and non-ASCII bytes escaped
/// (\n, \x1b), and cut to `max_chars` with the full length said.
std::string printable(const std::string& text, size_t max_chars = 80);

/// Deepest nesting of arrays and objects a file may have (no input is read
/// recursively beyond it).
constexpr int kMaxJsonDepth = 64;

/// "path.key" and "path[i]": JSON paths as errors print them (keys printable()).
std::string jsonPath(const std::string& path, const std::string& key);
std::string jsonPath(const std::string& path, size_t index);

// Typed getters of every reader (scenes, plans, tolerance files, the gallery's
// x-extreme): each throws InputError at `path`, in one phrasing for all.

/// The value of `key` in `obj`; else "missing required key".
const nlohmann::json& requireKey(const nlohmann::json& obj, const std::string& path, const char* key);
/// `obj` is an object whose keys are all `known` (or start with "x-": notes for
/// people); else "expected an object" or "unknown key (a, b, ...)".
void onlyKeys(const nlohmann::json& obj, const std::string& path, const std::vector<std::string>& known);
/// What a value is, for a message: its type, a short string's text (never a dump).
std::string describeJson(const nlohmann::json& v);
/// A finite number; else "expected a number, got ..." or "not a finite number".
double numberAt(const nlohmann::json& v, const std::string& path);
/// A finite number > 0; else "must be a finite number > 0".
double positiveAt(const nlohmann::json& v, const std::string& path);
/// A string; else "expected a string, got ...".
std::string stringAt(const nlohmann::json& v, const std::string& path);
/// true or false; else "expected true or false".
bool boolAt(const nlohmann::json& v, const std::string& path);
/// A whole number from lo to hi; else "must be a whole number from lo to hi (why)".
int wholeNumberAt(const nlohmann::json& v, const std::string& path, int lo, int hi, const std::string& why);
/// A list with at least one element; else "expected a non-empty list".
nlohmann::json nonEmptyArrayAt(const nlohmann::json& v, const std::string& path);

}  // namespace em
