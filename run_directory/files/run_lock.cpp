#include "run_directory/files/run_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <system_error>
#include <utility>

namespace poet {
namespace {

std::string errno_text() { return std::generic_category().message(errno); }

// The pid the holder wrote, or "unknown" (the file may be gone, or the holder between its lock and its pid).
std::string holder_pid(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) return "unknown";
  char buffer[32] = {};
  const ssize_t n = ::read(fd, buffer, sizeof buffer - 1);
  ::close(fd);
  std::string text = n > 0 ? std::string(buffer, static_cast<size_t>(n)) : std::string();
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return "unknown";
  return text;
}

}  // namespace

Expected<RunLock> RunLock::acquire(const std::filesystem::path& dir) {
  // the lock is on the directory itself, not on a file in it: a file's name can be removed or replaced while its
  // holder runs, and a second process would then lock a new file of the same name
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return Unexpected{dir.string() + ": cannot open: " + errno_text()};
  RunLock lock(fd);
  const std::filesystem::path pid_path = dir / kLockFile;
  while (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    if (errno == EINTR) continue;
    if (errno == EWOULDBLOCK)
      return Unexpected{dir.string() + " is in use by another process (pid " + holder_pid(pid_path) +
                        "); one process owns a run directory at a time"};
    return Unexpected{dir.string() + ": cannot lock: " + errno_text()};
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  const int pid_fd = ::open(pid_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_NOFOLLOW, 0644);
  const bool written = pid_fd >= 0 && ::write(pid_fd, pid.data(), pid.size()) == static_cast<ssize_t>(pid.size());
  if (pid_fd >= 0) ::close(pid_fd);
  if (!written) return Unexpected{pid_path.string() + ": cannot record the owner's pid: " + errno_text()};
  return lock;
}

bool RunLock::held_by_another_process(const std::filesystem::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);  // closing drops the probe's lock, if it got one
  return held;
}

RunLock::RunLock(RunLock&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}

RunLock& RunLock::operator=(RunLock&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

RunLock::~RunLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the lock
}

}  // namespace poet
