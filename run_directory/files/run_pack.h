#pragma once
// A run as one file, to move it between machines: what the run needs to go on and nothing derived.
//   checkpoint.pb    the state, as it is on disk (its own header and CRC)
//   events.jsonl     } cut to the sizes the checkpoint records, their CRC-32 checked against it: exactly the
//   pair_stats.csv   } history the state has seen, even when packed while the run goes on
//   wall_times.csv   the lines of the iterations the checkpoint has seen (absent when the run has none)
//   refused_keys.txt with CURVE, the public keys of workers refused for wrong results (absent when none)
// config.textproto, annecs.csv, envs/ and policies/ are functions of the checkpoint: the resume writes them again.
// The file:
//   offset 0   8 bytes   magic "POETPACK"
//   offset 8   uint32    format version (kPackFormatVersion), little-endian
//   offset 12  uint32    number of entries
//   then per entry: uint32 name length, the name, uint64 size, uint32 CRC-32 of the content, uint64 stored size,
//                   the content deflated (zlib) in stored-size bytes
//   last       uint32    CRC-32 of every byte before it
// A pack is checked whole before anything is written from it: a damaged, truncated or foreign file, an unknown or
// repeated entry, or logs that differ from what its checkpoint saw are refused with the reason.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/plumbing/expected.h"
#include "run_directory/files/checkpoint.h"

namespace poet {

inline constexpr std::string_view kPackMagic = "POETPACK";
inline constexpr uint32_t kPackFormatVersion = 1;
// A pack larger than this is refused unread (a checkpoint may be 1 GiB; the logs of a long run some more).
inline constexpr std::uintmax_t kMaxPackBytes = std::uintmax_t{4} << 30;

struct PackEntry {
  std::string name;  // a file of the run directory
  std::string content;
};

// What a pack holds, for the messages of the tools.
struct PackSummary {
  int next_iteration = 0;                     // the iteration the run does next
  std::optional<uint64_t> arithmetic_digest;  // of the process that wrote its checkpoint (checkpoint.h)
  std::optional<std::string> unknown_fields;  // unknown_fields_refusal of its checkpoint: a later build wrote it
  std::vector<PackEntry> entries;
  uint64_t pack_bytes = 0;
};

// The pack's bytes for these entries (no checks of their content).
std::string encode_pack(const std::vector<PackEntry>& entries);

// The entries of a pack's bytes, after checking the header, every entry and the trailing CRC; then that it holds
// checkpoint.pb, events.jsonl and pair_stats.csv, that the checkpoint reads, and that the logs are the sizes and
// CRC-32 it records. Errors say what is wrong ("truncated: ...", "CRC-32 mismatch: ..."), not where.
Expected<PackSummary> decode_pack(std::string_view bytes);

// Packs the run in run_dir into pack_path (written atomically; an existing file is replaced), then reads the
// file back and decodes it, so a pack that was written is one that restores. A pack_path inside run_dir is refused.
// Reads only: the run may be going on (the pack holds its last checkpoint). Errors name the file.
Expected<PackSummary> write_run_pack(const std::filesystem::path& run_dir, const std::filesystem::path& pack_path);

// Restores the pack at pack_path as the run directory run_dir, which must not exist or be an empty directory:
// the pack is checked whole, its files are written into a fresh directory beside run_dir and made durable, and
// that directory is renamed to run_dir. Nothing is written when the pack or the destination is refused, and an
// existing run directory is never overwritten, nor, for computing, is a pack restored that this process may not
// resume (unknown_fields_refusal, arithmetic_refusal). Resume the run there next (RunDirectory::resume).
Expected<PackSummary> restore_run_pack(const std::filesystem::path& pack_path, const std::filesystem::path& run_dir,
                                       OpenFor purpose = OpenFor::kComputing);

}  // namespace poet
