#include "run_directory/files/log_prefix.h"

#include <fstream>
#include <system_error>

#include "run_directory/files/crc32.h"
#include "run_directory/files/run_directory.h"

namespace poet {
namespace fs = std::filesystem;

Expected<std::string> read_log_prefix(const fs::path& path, int64_t size, std::optional<uint32_t> crc) {
  std::error_code ec;
  const std::uintmax_t present = fs::file_size(path, ec);
  if (ec) return Unexpected{path.string() + ": cannot read (" + ec.message() + "); the run directory is incomplete"};
  if (size < 0 || present < static_cast<std::uintmax_t>(size))
    return Unexpected{path.string() + ": " + std::to_string(present) + " bytes, but the checkpoint records " +
                      std::to_string(size) + " (the file was truncated or damaged)"};
  std::ifstream in(path, std::ios::binary);
  std::string bytes(static_cast<size_t>(size), '\0');
  if (!in.read(bytes.data(), size)) return Unexpected{path.string() + ": cannot read"};
  if (crc && crc32_extend(0, bytes) != *crc) return Unexpected{log_changed_error(path, size)};
  return bytes;
}

}  // namespace poet
