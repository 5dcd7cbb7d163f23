#pragma once
/// Output files appear whole or not at all: written to a temporary beside the
/// target, then renamed. A reader never sees half a file, and an interrupted
/// run leaves none.
#include <functional>
#include <ostream>
#include <string>

namespace em {

/// Write `path` through `write` atomically. Throws std::runtime_error naming
/// `path` ("path: cannot write the <what>") and leaves no temporary.
void writeAtomic(const std::string& path, const std::string& what, const std::function<void(std::ostream&)>& write);

/// On SIGINT or SIGTERM, remove the temporary being written (if any), then die
/// of the signal as before (exit status 130 or 143 in a shell). Programs call it once.
void installInterruptCleanup();

}  // namespace em
