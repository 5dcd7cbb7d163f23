#pragma once
// An engine's own messages on stderr, gathered into one line (issue 73, item
// 11: Simbody's CPodes printed 400+ "[CPODES ERROR] ... mxstep steps" lines
// for one failed reference). While resumed, file descriptor 2 goes to a
// temporary file; paused, it is the process's stderr again (our own progress
// lines print between an engine's steps, not inside them).
#include <string>

namespace em {

class EngineMessages {
 public:
  EngineMessages();
  ~EngineMessages();
  EngineMessages(const EngineMessages&) = delete;
  EngineMessages& operator=(const EngineMessages&) = delete;

  void resume();  ///< the engine's stderr into the file
  void pause();   ///< stderr back
  /// "" when nothing was printed; else one line: how many messages, the first
  /// and the last (each at most 200 characters), e.g. for a failure's cause.
  std::string summary(const std::string& engine) const;

 private:
  int saved_ = -1, file_ = -1;
  bool capturing_ = false;
};

}  // namespace em
