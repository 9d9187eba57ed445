#pragma once
// The on-disk form of a checkpoint: a fixed header, then the pb::Checkpoint message as the body.
//   offset 0   8 bytes   magic "POETCKPT"
//   offset 8   uint32    format version (kCheckpointFormatVersion), little-endian
//   offset 12  uint64    body length in bytes, little-endian
//   offset 20  uint32    CRC-32 (zlib's polynomial) of the body, little-endian
//   offset 24  body
// Protobuf accepts most flipped bytes as another valid message, so the checksum is what detects corruption; the
// length and the version make a truncated file and a file from another format clear errors of their own.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "common/plumbing/expected.h"
#include "poet.pb.h"

namespace poet {

inline constexpr std::string_view kCheckpointMagic = "POETCKPT";
inline constexpr uint32_t kCheckpointFormatVersion = 1;
inline constexpr size_t kCheckpointHeaderBytes = 24;

// A checkpoint file larger than this is refused unread: a pair takes about 90 KB, so this is some ten thousand.
inline constexpr std::uintmax_t kMaxCheckpointBytes = std::uintmax_t{1} << 30;

// Header and body of a checkpoint (the message serialised deterministically, so equal states give equal bytes).
std::string encode_checkpoint_file(const pb::Checkpoint& checkpoint);

// The message of a checkpoint file's bytes: the header checked (magic, version, length against the bytes
// present, checksum) before the body is parsed. Errors say what is wrong ("checksum mismatch: ..."), not where.
Expected<pb::Checkpoint> decode_checkpoint_file(std::string_view bytes);

// read_text_file (at most kMaxCheckpointBytes) then decode_checkpoint_file; every error starts with "<path>: ".
// The message is only decoded: from_checkpoint checks the state it describes.
Expected<pb::Checkpoint> read_checkpoint_file(const std::filesystem::path& path);

}  // namespace poet
