#pragma once
// Reading and writing the project's small files given as input (run configs, policies, environment definitions,
// checkpoints). Reads take regular files only, so they never block (a FIFO waits for a writer) nor read an endless
// device (/dev/zero), and are bounded, so a huge file is refused without being read whole; writes are atomic, so
// a reader sees the old file or the new one, never a part.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "common/plumbing/expected.h"

namespace poet {

// read_text_file's error when the path names nothing: absence, told apart from a file that cannot be read, so that
// a caller for whom a missing file is an outcome of its own needs no separate check (and no race with the read).
inline constexpr char kDoesNotExist[] = "does not exist";

// The whole file, or an error: kDoesNotExist, "is a directory", "is not a regular file (a FIFO)" (or a
// character device, a block device, a socket), "is larger than N bytes", or an I/O error. The type is checked
// before the file is opened and again on the open descriptor (the path may change in between), and the open does
// not block, so no file, not even a FIFO swapped in between the two checks, makes the call wait. Symbolic links
// are followed. Messages do not repeat the path: callers prefix it. Thread-safe.
Expected<std::string> read_text_file(const std::filesystem::path& path, std::uintmax_t max_bytes);

// Writes text to a fresh temporary file beside path (same file system), fsyncs it, renames it over path and
// fsyncs the directory. Returns an error message (without the path), or nothing on success; no temporary file
// is left behind either way.
std::optional<std::string> write_file_atomically(const std::filesystem::path& path, std::string_view text);

// Whether path names anything, following symbolic links. An error other than absence (a symbolic-link loop, a
// directory that cannot be searched) is returned as "cannot access: ..." rather than taken for "does not exist".
Expected<bool> path_exists(const std::filesystem::path& path);

// Whether path is dir or lies inside it (both made absolute, symbolic links resolved where they exist).
bool is_inside(const std::filesystem::path& path, const std::filesystem::path& dir);

// Writes all of text to fd, retrying short writes and interrupts. Returns errno, or 0.
int write_all(int fd, std::string_view text);

// Makes new entries of a directory (a rename, a created file) durable; best effort, as some file systems refuse
// fsync on a directory.
void sync_directory(const std::filesystem::path& dir);

// fsync(fd), retried on EINTR. Returns errno, or 0.
int fsync_retrying(int fd);

}  // namespace poet
