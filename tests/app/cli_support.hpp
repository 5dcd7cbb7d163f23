#pragma once
// The CLI tests' way of running the built tools as a user would.
#include <array>
#include <cstdio>
#include <sstream>
#include <string>

#include <sys/wait.h>

#include "support.hpp"

struct Run {
  int status;
  std::string out;
};

// Run the built eigenmass with arguments; stdout (and stderr if asked) captured,
// or, with `stdout_to`, stdout sent there and stderr captured.
// `program` is a built binary's name (eigenmass, eigenmass_bench).
inline Run tool(const std::string& program, const std::string& args, bool with_stderr = false, const std::string& stdout_to = "") {
  const std::string redirect = !stdout_to.empty() ? " 2>&1 >" + stdout_to : with_stderr ? " 2>&1" : " 2>/dev/null";
  const std::string cmd = std::string(EM_BINARY_DIR) + "/bin/" + program + " " + args + redirect;
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  while (size_t n = fread(buf.data(), 1, buf.size(), p)) out.append(buf.data(), n);
  const int st = pclose(p);
  return {WEXITSTATUS(st), out};
}

inline Run eigenmass(const std::string& args, bool with_stderr = false, const std::string& stdout_to = "") {
  return tool("eigenmass", args, with_stderr, stdout_to);
}

inline std::string scene(const std::string& name) { return em::test::sourcePath("data/scenes/" + name); }

// The line of `md` (a tables page) that starts with `prefix` ("" if none).
inline std::string lineOf(const std::string& md, const std::string& prefix) {
  std::istringstream in(md);
  for (std::string l; std::getline(in, l);)
    if (l.rfind(prefix, 0) == 0) return l;
  return "";
}
