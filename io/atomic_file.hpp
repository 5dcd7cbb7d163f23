#pragma once
/// Output files appear whole or not at all: written to a temporary beside the
/// target, then renamed. A reader never sees half a file, and an interrupted
/// run leaves none. Only a regular file (or a new one) is replaced so: a
/// character or block device or a FIFO is written into as it is (never
/// replaced: `--out /dev/null` as root stays the device), and a symbolic link
/// is followed, its target written atomically and the link kept (a link to a
/// missing file is refused). docs/report-format.md says so.
#include <functional>
#include <sys/types.h>

#include <ostream>
#include <string>

namespace em {

/// Write `path` through `write` atomically. Throws std::runtime_error naming
/// `path` ("path: cannot write the <what>") and leaves no temporary.
void writeAtomic(const std::string& path, const std::string& what, const std::function<void(std::ostream&)>& write);

/// Whether writeAtomic writes `path` straight through (a device, a FIFO or a
/// socket, or a link to one: /dev/stdout) rather than replacing a regular
/// file. Throws as writeAtomic does for a folder or a dangling link.
bool writesThrough(const std::string& path);

/// On SIGINT or SIGTERM, remove the temporary being written (if any), then die
/// of the signal as before (exit status 130 or 143 in a shell). Programs call it once.
void installInterruptCleanup();
/// The empty-at-the-end scratch folder to remove on such a signal ("": none).
void removeOnInterrupt(const std::string& folder);
/// Children to end (SIGTERM) and wait for on such a signal, before the folder
/// is removed: endOnInterrupt adds one (a drawing child, a sweep's workers; up
/// to kMaxChildren at once), releaseOnInterrupt forgets it once it is reaped.
inline constexpr int kMaxChildren = 1024;
void endOnInterrupt(pid_t child);
void releaseOnInterrupt(pid_t child);
/// In a child just forked from `parent`: the kernel sends it `sig` when the
/// parent dies by any path, SIGKILL included (PR_SET_PDEATHSIG; SIGTERM runs
/// this process's cleanup of its own temporary), and it forgets the parent's
/// other children. False where the parent was gone before that took: exit then.
bool dieWithParent(pid_t parent, int sig);

/// A program's exit code once what it printed must have reached standard
/// output: `code`, or 2 (with one line on standard error, `program` naming
/// it) when the writes failed (a full disk, a closed file). Programs end with it.
int finishStandardOutput(const char* program, int code);

}  // namespace em
