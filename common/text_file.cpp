#include "text_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <fstream>
#include <system_error>

namespace poet {
namespace {

std::string errno_text(int err) { return std::generic_category().message(err); }  // strerror is not thread-safe

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

Expected<std::string> read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) return Unexpected{"cannot access: " + ec.message()};
  if (!std::filesystem::exists(status)) return Unexpected{"does not exist"};
  if (std::filesystem::is_directory(status)) return Unexpected{"is a directory"};
  std::ifstream in(path, std::ios::binary);
  if (!in) return Unexpected{"cannot open"};
  std::string text;
  char buffer[1 << 16];
  while (in && text.size() <= max_bytes) {
    in.read(buffer, sizeof buffer);
    text.append(buffer, static_cast<size_t>(in.gcount()));
  }
  if (in.bad()) return Unexpected{"read error"};
  if (text.size() > max_bytes) return Unexpected{"is larger than " + std::to_string(max_bytes) + " bytes"};
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

}  // namespace poet
