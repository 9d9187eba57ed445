#pragma once
// One owner per run directory: an advisory lock (flock) on <dir>/run.lock, held for the life of the RunLock.
// The kernel drops the lock when its holder dies, however it dies, so a lock file left behind by a dead
// process never blocks; the file's content is only the holder's pid, for the message a second process gets.

#include <filesystem>

#include "expected.h"

namespace poet {

inline constexpr char kLockFile[] = "run.lock";

class RunLock {
 public:
  // Takes the lock on dir (which must exist) without waiting. When another process holds it, the error names
  // the holder: "<dir> is in use by another process (pid 4242); one process owns a run directory at a time".
  static Expected<RunLock> acquire(const std::filesystem::path& dir);

  RunLock(RunLock&& other) noexcept;
  RunLock& operator=(RunLock&& other) noexcept;
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;
  ~RunLock();

 private:
  explicit RunLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace poet
