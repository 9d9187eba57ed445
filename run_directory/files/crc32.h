#pragma once
// CRC-32 (zlib's polynomial) of bytes in memory, extended piece by piece, and of a file's first bytes: the
// checksum of checkpoint files and of the run's logs as far as a checkpoint has seen them.

#include <cstdint>
#include <filesystem>
#include <string_view>

#include "common/plumbing/expected.h"

namespace poet {

// The CRC-32 of the bytes seen so far (`crc`, 0 for none) followed by `bytes`.
uint32_t crc32_extend(uint32_t crc, std::string_view bytes);

// The CRC-32 of the first `size` bytes of the file; an error naming it when it is shorter or cannot be read.
Expected<uint32_t> file_prefix_crc32(const std::filesystem::path& path, int64_t size);

}  // namespace poet
