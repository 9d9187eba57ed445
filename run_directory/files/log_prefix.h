#pragma once
// Reading a run log as far as a checkpoint has seen it: the checkpoint records each log's size and CRC-32, so
// the bytes a reader takes are exactly the state's history, whatever a live run appended since.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "common/plumbing/expected.h"

namespace poet {

// The first `size` bytes of a log, or an error naming the file when it is missing or shorter (the checkpoint was
// written after the logs were made durable, so a shorter log was damaged after the fact) or, when the checkpoint
// has their CRC-32 (`crc`), they differ from what it saw.
Expected<std::string> read_log_prefix(const std::filesystem::path& path, int64_t size, std::optional<uint32_t> crc);

}  // namespace poet
