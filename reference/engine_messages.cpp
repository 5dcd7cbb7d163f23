#include "reference/engine_messages.hpp"

#include "solver/text.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

namespace em {

namespace {
// Read at most this much of what an engine printed (1e5 CPODES lines are ~6 MB).
constexpr long kReadMax = 1 << 20;

std::string trimmed(const std::string& s, size_t max) {
  const size_t b = s.find_first_not_of(" \t\r"), e = s.find_last_not_of(" \t\r");
  std::string t = b == std::string::npos ? "" : s.substr(b, e - b + 1);
  for (char& c : t)
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  return t.size() > max ? t.substr(0, max) + "..." : t;
}
}  // namespace

EngineMessages::EngineMessages() {
  char path[] = "/tmp/eigenmass-engine-XXXXXX";
  file_ = mkstemp(path);
  if (file_ >= 0) unlink(path);  // gone when closed
  saved_ = dup(2);
}

EngineMessages::~EngineMessages() {
  pause();
  if (file_ >= 0) close(file_);
  if (saved_ >= 0) close(saved_);
}

void EngineMessages::resume() {
  if (capturing_ || file_ < 0 || saved_ < 0) return;
  std::fflush(stderr);
  g_stderr_fd = saved_;  // before fd 2 moves: an interrupt's last line still reaches stderr
  if (dup2(file_, 2) >= 0) capturing_ = true;
  else g_stderr_fd = 2;
}

void EngineMessages::pause() {
  if (!capturing_) return;
  std::fflush(stderr);
  dup2(saved_, 2);
  g_stderr_fd = 2;
  capturing_ = false;
}

std::string EngineMessages::summary(const std::string& engine) const {
  if (file_ < 0) return "";
  const off_t size = lseek(file_, 0, SEEK_END);
  if (size <= 0) return "";
  std::string text(static_cast<size_t>(std::min<off_t>(size, kReadMax)), '\0');
  if (pread(file_, text.data(), text.size(), 0) <= 0) return "";
  // A message is a header line ("[CPODES ERROR]  CPode") and its text, or one line.
  std::vector<std::string> messages;
  size_t pos = 0;
  bool header = false;
  while (pos < text.size()) {
    size_t nl = text.find('\n', pos);
    if (nl == std::string::npos) nl = text.size();
    const std::string line = trimmed(text.substr(pos, nl - pos), 200);
    pos = nl + 1;
    if (line.empty()) continue;
    if (line.front() == '[') {
      messages.push_back(line);
      header = true;
    } else if (header) {
      messages.back() = line;  // the header's text
      header = false;
    } else {
      messages.push_back(line);
    }
  }
  if (messages.empty()) return "";
  std::string s = engine + " printed " + std::to_string(messages.size()) + (messages.size() == 1 ? " message" : " messages") +
                  (size > kReadMax ? " (in its first MB)" : "") + ": first '" + messages.front() + "'";
  if (messages.size() > 1) s += ", last '" + messages.back() + "'";
  return s;
}

}  // namespace em
