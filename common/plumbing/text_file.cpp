#include "common/plumbing/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <system_error>

namespace poet {
namespace {

std::string errno_text(int err) { return std::generic_category().message(err); }  // strerror is not thread-safe

// Why a file of this type is refused, or nothing for a regular file.
std::optional<std::string> refusal(mode_t mode) {
  if (S_ISREG(mode)) return std::nullopt;
  if (S_ISDIR(mode)) return "is a directory";
  if (S_ISFIFO(mode)) return "is not a regular file (a FIFO)";
  if (S_ISCHR(mode)) return "is not a regular file (a character device)";
  if (S_ISBLK(mode)) return "is not a regular file (a block device)";
  if (S_ISSOCK(mode)) return "is not a regular file (a socket)";
  return "is not a regular file";
}

// Closes the descriptor on every path out.
struct FdCloser {
  int fd;
  ~FdCloser() { ::close(fd); }
};

}  // namespace

int write_all(int fd, std::string_view text) {
  while (!text.empty()) {
    const ssize_t n = ::write(fd, text.data(), text.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    text.remove_prefix(static_cast<size_t>(n));
  }
  return 0;
}

void sync_directory(const std::filesystem::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

int fsync_retrying(int fd) {
  while (::fsync(fd) != 0) {
    if (errno != EINTR) return errno;
  }
  return 0;
}

Expected<bool> path_exists(const std::filesystem::path& path) {
  std::error_code ec;
  const bool exists = std::filesystem::exists(path, ec);
  if (ec) return Unexpected{"cannot access: " + ec.message()};
  return exists;
}

Expected<std::string> read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  // refuse what is not a regular file before opening it: opening a FIFO for reading waits for a writer
  struct stat before {};
  if (::stat(path.c_str(), &before) != 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR) return Unexpected{kDoesNotExist};
    return Unexpected{"cannot access: " + errno_text(err)};
  }
  if (auto why = refusal(before.st_mode)) return Unexpected{*why};

  // the path may name something else by now: O_NONBLOCK keeps a FIFO swapped in from blocking the open, and the
  // open descriptor is checked again
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR) return Unexpected{kDoesNotExist};
    return Unexpected{"cannot open: " + errno_text(err)};
  }
  const FdCloser closer{fd};
  struct stat opened {};
  if (::fstat(fd, &opened) != 0) return Unexpected{"cannot access: " + errno_text(errno)};
  if (auto why = refusal(opened.st_mode)) return Unexpected{*why};
  const std::string too_large = "is larger than " + std::to_string(max_bytes) + " bytes";
  if (static_cast<std::uintmax_t>(opened.st_size) > max_bytes) return Unexpected{too_large};

  // read to the end, but never more than one byte past the limit (the file may grow while it is read, and some
  // files, such as those of /proc, report size 0)
  std::string text;
  char buffer[1 << 16];
  while (text.size() <= max_bytes) {
    const std::uintmax_t wanted = std::min<std::uintmax_t>(sizeof buffer, max_bytes - text.size() + 1);
    const ssize_t n = ::read(fd, buffer, static_cast<size_t>(wanted));
    if (n < 0) {
      if (errno == EINTR) continue;
      return Unexpected{"read error: " + errno_text(errno)};
    }
    if (n == 0) break;
    text.append(buffer, static_cast<size_t>(n));
  }
  if (text.size() > max_bytes) return Unexpected{too_large};
  return text;
}

std::optional<std::string> write_file_atomically(const std::filesystem::path& path, std::string_view text) {
  // O_EXCL never clobbers a concurrent writer's temporary
  static std::atomic<unsigned> counter{0};
  std::filesystem::path tmp;
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    tmp = path;
    tmp += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) return "cannot create temporary file " + tmp.string() + ": " + errno_text(errno);

  int err = write_all(fd, text);
  if (err == 0) err = fsync_retrying(fd);
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err == 0 && ::rename(tmp.c_str(), path.c_str()) != 0) err = errno;
  if (err != 0) {
    ::unlink(tmp.c_str());
    return errno_text(err);
  }
  sync_directory(path.parent_path());
  return std::nullopt;
}

bool is_inside(const std::filesystem::path& path, const std::filesystem::path& dir) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(path), ec);
  const std::filesystem::path d = std::filesystem::weakly_canonical(std::filesystem::absolute(dir), ec);
  auto pi = p.begin();
  for (auto di = d.begin(); di != d.end(); ++di, ++pi) {
    if (di->empty()) continue;  // a trailing separator
    if (pi == p.end() || *pi != *di) return false;
  }
  return true;
}

}  // namespace poet
