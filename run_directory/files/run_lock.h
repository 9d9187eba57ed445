#pragma once
// One owner per run directory: an advisory lock (flock) on the directory itself, held for the life of the RunLock.
// The kernel drops the lock when its holder dies, however it dies, so nothing left behind by a dead process
// blocks; and removing or replacing any file in the directory cannot release it. <dir>/run.lock only holds the
// owner's pid, for the message a second process gets.

#include <filesystem>

#include "common/plumbing/expected.h"

namespace poet {

inline constexpr char kLockFile[] = "run.lock";

class RunLock {
 public:
  // Takes the lock on dir (which must exist) without waiting. When another process holds it, the error names
  // the holder: "<dir> is in use by another process (pid 4242); one process owns a run directory at a time".
  static Expected<RunLock> acquire(const std::filesystem::path& dir);

  // Whether another process owns dir now: a non-blocking shared lock, released at once (a reader's probe; it
  // never blocks the owner for longer than the probe).
  static bool held_by_another_process(const std::filesystem::path& dir);

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
