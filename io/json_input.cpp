#include "io/json_input.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

namespace em {

namespace {

using json = nlohmann::json;

// The JSON path of the value being parsed, from nlohmann's parse events.
struct PathTracker {
  struct Frame {
    explicit Frame(bool is_array) : array(is_array) {}
    bool array;
    long count = 0;   // completed elements of an array: the index of the one being read
    std::string key;  // current key of an object
    std::set<std::string> keys;
  };
  std::vector<Frame> stack;
  std::string duplicate;

  std::string path() const {
    std::string p;
    for (const Frame& f : stack) {
      if (f.array) p += "[" + std::to_string(f.count) + "]";
      else if (!f.key.empty()) p += (p.empty() ? "" : ".") + printable(f.key);
    }
    return p.empty() ? "(document)" : p;
  }
  // nlohmann emits `value` only for primitives; a container completes at its end event.
  void completed() {
    if (!stack.empty() && stack.back().array) ++stack.back().count;
  }
  bool operator()(int, json::parse_event_t ev, json& parsed) {
    using E = json::parse_event_t;
    switch (ev) {
      case E::object_start:
      case E::array_start:
        if (stack.size() >= static_cast<size_t>(kMaxJsonDepth))
          throw InputError(path(), "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        stack.emplace_back(ev == E::array_start);
        break;
      case E::object_end:
      case E::array_end: stack.pop_back(); completed(); break;
      case E::key:
        stack.back().key = parsed.get<std::string>();
        if (!stack.back().keys.insert(stack.back().key).second && duplicate.empty()) duplicate = path();
        break;
      case E::value: completed(); break;
    }
    return true;
  }
};

std::string lineColumn(const std::string& text, size_t byte) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i + 1 < byte && i < text.size(); ++i) {
    if (text[i] == '\n') { ++line; col = 1; } else { ++col; }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

}  // namespace

json parseJsonStrict(const std::string& text) {
  PathTracker tracker;
  json doc;
  try {
    doc = json::parse(text, [&tracker](int depth, json::parse_event_t ev, json& parsed) {
      return tracker(depth, ev, parsed);
    });
  } catch (const json::parse_error& e) {
    throw InputError("(document)", "invalid JSON at " + lineColumn(text, e.byte));
  } catch (const json::exception& e) {
    // out_of_range.406: a number too large for a double (1e999), at the tracked path.
    const std::string w = e.what();
    throw InputError(tracker.path(), w.substr(w.find(']') + 2) + " (not a finite number)");
  }
  if (!tracker.duplicate.empty()) throw InputError(tracker.duplicate, "duplicate key");
  return doc;
}

json readJsonFile(const std::string& path, const std::string& what) {
  const std::string text = readFile(path, what);
  try {
    return parseJsonStrict(text);
  } catch (const InputError& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

std::string readFile(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw std::runtime_error(path + ": is a folder, not a " + what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open the " + what);
  // Bounded: /dev/zero or a runaway file ends in one line, not in memory exhaustion.
  std::string text;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
    text.append(chunk, static_cast<size_t>(in.gcount()));
    if (text.size() > kMaxInputBytes)
      throw std::runtime_error(path + ": larger than " + std::to_string(kMaxInputBytes >> 20) + " MiB: not a " + what);
  }
  return text;
}

std::string printable(const std::string& text, size_t max_chars) {
  std::string out;
  size_t shown = 0;
  for (; shown < text.size() && out.size() < max_chars; ++shown) {
    const unsigned char c = static_cast<unsigned char>(text[shown]);
    if (c == '\n') out += "\\n";
    else if (c == '\t') out += "\\t";
    else if (c == '\\') out += "\\\\";
    else if (c < 0x20 || c >= 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    } else out += static_cast<char>(c);
  }
  if (shown < text.size()) out += "... (" + std::to_string(text.size()) + " bytes)";
  return out;
}

std::string jsonPath(const std::string& path, const std::string& key) {
  return path.empty() ? printable(key) : path + "." + printable(key);
}
std::string jsonPath(const std::string& path, size_t index) { return path + "[" + std::to_string(index) + "]"; }

const nlohmann::json& requireKey(const nlohmann::json& obj, const std::string& path, const char* key) {
  auto it = obj.find(key);
  if (it == obj.end()) throw InputError(jsonPath(path, key), "missing required key");
  return *it;
}

void onlyKeys(const nlohmann::json& obj, const std::string& path, const std::vector<std::string>& known) {
  if (!obj.is_object()) throw InputError(path.empty() ? "(document)" : path, "expected an object");
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    if (it.key().rfind("x-", 0) == 0) continue;
    bool ok = false;
    for (const std::string& k : known) ok = ok || it.key() == k;
    if (ok) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    throw InputError(jsonPath(path, it.key()), "unknown key (" + list + ")");
  }
}

std::string describeJson(const nlohmann::json& v) {
  if (v.is_string()) return "string \"" + printable(v.get<std::string>(), 40) + "\"";
  if (v.is_array()) return "a list of " + std::to_string(v.size());
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  return v.type_name();
}

double numberAt(const nlohmann::json& v, const std::string& path) {
  if (!v.is_number()) throw InputError(path, "expected a number, got " + describeJson(v));
  const double x = v.get<double>();
  if (!std::isfinite(x)) throw InputError(path, "not a finite number");
  return x;
}

double positiveAt(const nlohmann::json& v, const std::string& path) {
  if (!v.is_number() || !std::isfinite(v.get<double>()) || !(v.get<double>() > 0))
    throw InputError(path, "must be a finite number > 0");
  return v.get<double>();
}

std::string stringAt(const nlohmann::json& v, const std::string& path) {
  if (!v.is_string()) throw InputError(path, "expected a string, got " + describeJson(v));
  return v.get<std::string>();
}

bool boolAt(const nlohmann::json& v, const std::string& path) {
  if (!v.is_boolean()) throw InputError(path, "expected true or false");
  return v.get<bool>();
}

int wholeNumberAt(const nlohmann::json& v, const std::string& path, int lo, int hi, const std::string& why) {
  if (!v.is_number_integer() || v.get<long>() < lo || v.get<long>() > hi)
    throw InputError(path, "must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) + " (" + why + ")");
  return v.get<int>();
}

nlohmann::json nonEmptyArrayAt(const nlohmann::json& v, const std::string& path) {
  if (!v.is_array() || v.empty()) throw InputError(path, "expected a non-empty list");
  return v;
}

}  // namespace em
