#pragma once
// Reading and writing the project's small text files (policies, environment definitions, and later run state).
// Reads are bounded, so a huge or endless file (a FIFO, /dev/zero) is refused without being read whole; writes
// are atomic, so a reader sees the old file or the new one, never a part.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "expected.h"

namespace poet {

// The whole file, or an error ("does not exist", "is a directory", "is larger than N bytes", an I/O error).
// Messages do not repeat the path: callers prefix it.
Expected<std::string> read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes);

// Writes text to a fresh temporary file beside path (same file system), fsyncs it, renames it over path and
// fsyncs the directory. Returns an error message (without the path), or nothing on success; no temporary file
// is left behind either way.
std::optional<std::string> write_file_atomically(const std::filesystem::path& path, std::string_view text);

// Writes all of text to fd, retrying short writes and interrupts. Returns errno, or 0.
int write_all(int fd, std::string_view text);

// Makes new entries of a directory (a rename, a created file) durable; best effort, as some file systems refuse
// fsync on a directory.
void sync_directory(const std::filesystem::path& dir);

// fsync(fd), retried on EINTR. Returns errno, or 0.
int fsync_retrying(int fd);

}  // namespace poet
