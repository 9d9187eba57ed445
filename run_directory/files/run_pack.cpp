#include "run_directory/files/run_pack.h"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <optional>
#include <system_error>

#include "common/plumbing/curve_keys.h"
#include "common/plumbing/text_file.h"
#include "engine/run_state.h"
#include "run_directory/files/checkpoint.h"
#include "run_directory/files/checkpoint_file.h"
#include "run_directory/files/crc32.h"
#include "run_directory/files/little_endian.h"
#include "run_directory/files/log_prefix.h"
#include "run_directory/files/run_directory.h"
#include "run_directory/files/wall_times.h"

namespace poet {
namespace fs = std::filesystem;
namespace {

constexpr std::array<const char*, 5> kPackedFiles = {kCheckpointFile, kEventsFile, kStatsFile, kWallTimesFile,
                                                     kRefusedKeysFile};

// The lines of refused_keys.txt that are keys (the coordinator skips the rest too), or the first that is not.
std::string refused_keys_text(std::string_view text) {
  std::string out;
  for (size_t start = 0; start < text.size();) {
    const size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view line = text.substr(start, end - start);
    if (is_z85_key(line)) out.append(line).append("\n");
    start = end + 1;
  }
  return out;
}
// deflate never does better than about 1032:1, so a larger claimed size is a lie told to make us allocate
constexpr uint64_t kMaxDeflateRatio = 1032;
constexpr uint64_t kMaxEntryBytes = uint64_t{2} << 30;

// Reads little-endian fields from the front of the bytes; every read says whether the bytes were long enough.
class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  bool u32(uint32_t& v) { return number(v, 4); }
  bool u64(uint64_t& v) { return number(v, 8); }
  bool take(uint64_t n, std::string_view& out) {
    if (n > bytes_.size()) return false;
    out = bytes_.substr(0, static_cast<size_t>(n));
    bytes_.remove_prefix(static_cast<size_t>(n));
    return true;
  }
  size_t left() const { return bytes_.size(); }

 private:
  template <class T>
  bool number(T& v, int n) {
    if (bytes_.size() < static_cast<size_t>(n)) return false;
    v = static_cast<T>(get_le(bytes_, 0, n));
    bytes_.remove_prefix(static_cast<size_t>(n));
    return true;
  }
  std::string_view bytes_;
};

std::string deflate_bytes(std::string_view raw) {
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string out(size, '\0');
  const int rc = compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(raw.data()),
                           static_cast<uLong>(raw.size()), Z_BEST_COMPRESSION);
  if (rc != Z_OK) throw std::bad_alloc();  // Z_MEM_ERROR; the buffer is compressBound's, so never Z_BUF_ERROR
  out.resize(size);
  return out;
}

Expected<std::string> inflate_bytes(std::string_view stored, uint64_t raw_size, const std::string& name) {
  if (raw_size > kMaxEntryBytes || raw_size > (stored.size() + 1) * kMaxDeflateRatio)
    return Unexpected{name + ": claims " + std::to_string(raw_size) + " bytes from " + std::to_string(stored.size()) +
                      " stored (not a pack this project wrote)"};
  std::string raw(static_cast<size_t>(raw_size), '\0');
  uLongf size = static_cast<uLongf>(raw_size);
  uLong consumed = static_cast<uLong>(stored.size());
  const int rc = uncompress2(reinterpret_cast<Bytef*>(raw.data()), &size, reinterpret_cast<const Bytef*>(stored.data()),
                             &consumed);
  if (rc != Z_OK || size != raw_size || consumed != stored.size())
    return Unexpected{name + ": its compressed bytes are damaged (zlib: " +
                      (rc == Z_OK ? std::string("wrong length") : std::string(zError(rc))) + ")"};
  return raw;
}

// The checks of the whole: the run's files are there, the checkpoint reads, the logs are what it saw.
Expected<PackSummary> check_entries(std::vector<PackEntry> entries) {
  auto find = [&](const char* name) -> const PackEntry* {
    for (const PackEntry& e : entries)
      if (e.name == name) return &e;
    return nullptr;
  };
  for (const char* required : {kCheckpointFile, kEventsFile, kStatsFile})
    if (!find(required)) return Unexpected{std::string("no ") + required + " in the pack"};
  Expected<pb::Checkpoint> checkpoint = decode_checkpoint_file(find(kCheckpointFile)->content);
  if (!checkpoint) return Unexpected{std::string(kCheckpointFile) + ": " + checkpoint.error()};
  const std::optional<std::string> unknown_fields = unknown_fields_refusal(*checkpoint);
  Expected<RunState> state = from_checkpoint(*checkpoint);
  if (!state)  // a later build's rules may be what the state breaks: say so
    return Unexpected{std::string(kCheckpointFile) + ": " + state.error() +
                      (unknown_fields ? " (" + *unknown_fields + ")" : std::string())};
  const struct {
    const char* name;
    bool has_size;
    int64_t size;
    bool has_crc;
    uint32_t crc;
  } logs[] = {{kEventsFile, checkpoint->has_events_bytes(), checkpoint->events_bytes(), checkpoint->has_events_crc32(),
               checkpoint->events_crc32()},
              {kStatsFile, checkpoint->has_stats_bytes(), checkpoint->stats_bytes(), checkpoint->has_stats_crc32(),
               checkpoint->stats_crc32()}};
  for (const auto& log : logs) {
    if (!log.has_size) return Unexpected{std::string(kCheckpointFile) + ": records no size of " + log.name};
    const std::string& content = find(log.name)->content;
    if (log.size < 0 || content.size() != static_cast<uint64_t>(log.size))
      return Unexpected{std::string(log.name) + ": " + std::to_string(content.size()) +
                        " bytes, but the checkpoint records " + std::to_string(log.size)};
    if (log.has_crc && crc32_extend(0, content) != log.crc)
      return Unexpected{std::string(log.name) + ": its bytes differ from those the checkpoint has seen (CRC-32)"};
  }
  if (const PackEntry* wall = find(kWallTimesFile)) {
    Expected<std::vector<WallTime>> lines = parse_wall_times(wall->content);
    if (!lines) return Unexpected{std::string(kWallTimesFile) + ": " + lines.error()};
    if (!lines->empty() && lines->back().iteration >= state->next_iteration)
      return Unexpected{std::string(kWallTimesFile) + ": times iteration " + std::to_string(lines->back().iteration) +
                        ", which the checkpoint has not seen"};
  }
  if (const PackEntry* keys = find(kRefusedKeysFile);
      keys != nullptr && refused_keys_text(keys->content) != keys->content)
    return Unexpected{std::string(kRefusedKeysFile) + ": holds a line that is not a CURVE public key"};
  PackSummary summary;
  summary.next_iteration = state->next_iteration;
  if (checkpoint->has_arithmetic_digest()) summary.arithmetic_digest = checkpoint->arithmetic_digest();
  summary.unknown_fields = unknown_fields;
  summary.entries = std::move(entries);
  return summary;
}

// The destination of a restore, made absolute and without a trailing separator; an error when it is taken.
Expected<fs::path> free_destination(const fs::path& run_dir) {
  std::error_code ec;
  fs::path dir = fs::absolute(run_dir, ec).lexically_normal();
  if (ec) return Unexpected{run_dir.string() + ": " + ec.message()};
  if (!dir.has_filename()) dir = dir.parent_path();
  if (!dir.has_filename() || dir == dir.root_path()) return Unexpected{run_dir.string() + ": not a directory to make"};
  const fs::file_status status = fs::symlink_status(dir, ec);
  if (fs::exists(status)) {
    if (!fs::is_directory(status))
      return Unexpected{run_dir.string() + ": exists and is not a directory (a pack is restored into a new one)"};
    if (!fs::is_empty(dir, ec) || ec)
      return Unexpected{run_dir.string() +
                        ": exists and is not empty; a pack is restored only into a new or empty directory, and a "
                        "run directory is never overwritten"};
  }
  return dir;
}

}  // namespace

std::string encode_pack(const std::vector<PackEntry>& entries) {
  std::string out(kPackMagic);
  put_le(out, kPackFormatVersion, 4);
  put_le(out, entries.size(), 4);
  for (const PackEntry& e : entries) {
    const std::string stored = deflate_bytes(e.content);
    put_le(out, e.name.size(), 4);
    out += e.name;
    put_le(out, e.content.size(), 8);
    put_le(out, crc32_extend(0, e.content), 4);
    put_le(out, stored.size(), 8);
    out += stored;
  }
  put_le(out, crc32_extend(0, out), 4);
  return out;
}

Expected<PackSummary> decode_pack(std::string_view bytes) {
  if (bytes.size() < kPackMagic.size() || bytes.substr(0, kPackMagic.size()) != kPackMagic)
    return Unexpected{"not a run pack (no POETPACK header)"};
  if (bytes.size() < kPackMagic.size() + 12) return Unexpected{"truncated: the header is cut short"};
  uint32_t trailer = 0;
  Reader tail(bytes.substr(bytes.size() - 4));
  tail.u32(trailer);
  const std::string_view body = bytes.substr(0, bytes.size() - 4);
  Reader in(body.substr(kPackMagic.size()));
  uint32_t version = 0, count = 0;
  in.u32(version);
  in.u32(count);
  if (version != kPackFormatVersion)
    return Unexpected{"format version " + std::to_string(version) + ", this build reads version " +
                      std::to_string(kPackFormatVersion)};
  if (count > kPackedFiles.size()) return Unexpected{std::to_string(count) + " entries: not a pack this project wrote"};
  // the entries' frames first, so that a truncated file is called truncated rather than a checksum mismatch
  struct Stored {
    std::string name;
    uint64_t raw_size = 0;
    uint32_t crc = 0;
    std::string_view bytes;
  };
  std::vector<Stored> stored;
  for (uint32_t i = 0; i < count; ++i) {
    const std::string where = "entry " + std::to_string(i + 1);
    uint32_t name_size = 0;
    std::string_view name;
    uint64_t stored_size = 0;
    Stored e;
    if (!in.u32(name_size) || name_size > 64 || !in.take(name_size, name) || !in.u64(e.raw_size) || !in.u32(e.crc) ||
        !in.u64(stored_size) || !in.take(stored_size, e.bytes))
      return Unexpected{"truncated: " + where + " is cut short (" + std::to_string(bytes.size()) +
                        " bytes in the file)"};
    e.name = std::string(name);
    if (std::none_of(kPackedFiles.begin(), kPackedFiles.end(), [&](const char* f) { return e.name == f; }))
      return Unexpected{where + ": \"" + e.name + "\" is not a file of a run pack"};
    if (std::any_of(stored.begin(), stored.end(), [&](const Stored& s) { return s.name == e.name; }))
      return Unexpected{where + ": " + e.name + " comes twice"};
    stored.push_back(e);
  }
  if (in.left() != 0)
    return Unexpected{"truncated or extended: " + std::to_string(in.left()) + " bytes after the last entry"};
  if (crc32_extend(0, body) != trailer) return Unexpected{"CRC-32 mismatch: the pack is damaged"};
  std::vector<PackEntry> entries;
  for (const Stored& e : stored) {
    Expected<std::string> raw = inflate_bytes(e.bytes, e.raw_size, e.name);
    if (!raw) return Unexpected{raw.error()};
    if (crc32_extend(0, *raw) != e.crc) return Unexpected{e.name + ": CRC-32 mismatch: its content is damaged"};
    entries.push_back({e.name, std::move(*raw)});
  }
  Expected<PackSummary> summary = check_entries(std::move(entries));
  if (summary) summary->pack_bytes = bytes.size();
  return summary;
}

Expected<PackSummary> write_run_pack(const fs::path& run_dir, const fs::path& pack_path) {
  std::error_code ec;
  if (!fs::is_directory(run_dir, ec)) return Unexpected{run_dir.string() + ": no such directory"};
  const fs::path checkpoint_path = run_dir / kCheckpointFile;
  Expected<std::string> checkpoint_bytes = read_text_file(checkpoint_path, kMaxCheckpointBytes);
  if (!checkpoint_bytes)
    return Unexpected{checkpoint_path.string() + ": " + checkpoint_bytes.error() + " (not a run directory?)"};
  Expected<pb::Checkpoint> checkpoint = decode_checkpoint_file(*checkpoint_bytes);
  if (!checkpoint) return Unexpected{checkpoint_path.string() + ": " + checkpoint.error()};
  if (!checkpoint->has_events_bytes() || !checkpoint->has_stats_bytes())
    return Unexpected{checkpoint_path.string() + ": no log sizes recorded (not a run directory's checkpoint)"};
  const int next_iteration = checkpoint->next_iteration();
  if (is_inside(pack_path, run_dir))
    return Unexpected{pack_path.string() + ": inside the run directory " + run_dir.string() +
                      "; a pack is written elsewhere (it would replace or add to the run's files)"};

  std::vector<PackEntry> entries = {{kCheckpointFile, std::move(*checkpoint_bytes)}};
  const auto crc = [](bool has, uint32_t value) { return has ? std::optional<uint32_t>(value) : std::nullopt; };
  Expected<std::string> events = read_log_prefix(run_dir / kEventsFile, checkpoint->events_bytes(),
                                                 crc(checkpoint->has_events_crc32(), checkpoint->events_crc32()));
  if (!events) return Unexpected{events.error()};
  entries.push_back({kEventsFile, std::move(*events)});
  Expected<std::string> stats = read_log_prefix(run_dir / kStatsFile, checkpoint->stats_bytes(),
                                                crc(checkpoint->has_stats_crc32(), checkpoint->stats_crc32()));
  if (!stats) return Unexpected{stats.error()};
  entries.push_back({kStatsFile, std::move(*stats)});
  // the machine's record: a damaged file is refused (its times would be lost on the other machine unsaid)
  const fs::path wall_path = run_dir / kWallTimesFile;
  if (Expected<std::vector<WallTime>> lines = read_wall_times(wall_path)) {
    std::erase_if(*lines, [&](const WallTime& w) { return w.iteration >= next_iteration; });
    entries.push_back({kWallTimesFile, wall_times_text(*lines)});
  } else if (lines.error() != kDoesNotExist) {
    return Unexpected{wall_path.string() + ": " + lines.error() + " (move it away to pack the run without its times)"};
  }
  // with CURVE, the keys of workers refused for wrong results: they stay refused where the run goes on
  const fs::path keys_path = run_dir / kRefusedKeysFile;
  if (Expected<std::string> keys = read_text_file(keys_path, kMaxRefusedKeysBytes)) {
    entries.push_back({kRefusedKeysFile, refused_keys_text(*keys)});
  } else if (keys.error() != kDoesNotExist) {
    return Unexpected{keys_path.string() + ": " + keys.error()};
  }

  const std::string bytes = encode_pack(entries);
  if (auto error = write_file_atomically(pack_path, bytes)) return Unexpected{pack_path.string() + ": " + *error};
  // verified as the file now is on disk: what a restore will read
  Expected<std::string> written = read_text_file(pack_path, kMaxPackBytes);
  if (!written) return Unexpected{pack_path.string() + ": cannot read back: " + written.error()};
  Expected<PackSummary> summary = decode_pack(*written);
  if (!summary) return Unexpected{pack_path.string() + ": written, but does not read back: " + summary.error()};
  for (size_t i = 0; i < entries.size(); ++i)
    if (summary->entries.size() != entries.size() || summary->entries[i].name != entries[i].name ||
        summary->entries[i].content != entries[i].content)
      return Unexpected{pack_path.string() + ": written, but reads back other content than was packed"};
  return summary;
}

Expected<PackSummary> restore_run_pack(const fs::path& pack_path, const fs::path& run_dir, OpenFor purpose) {
  Expected<fs::path> dir = free_destination(run_dir);
  if (!dir) return Unexpected{dir.error()};
  Expected<std::string> bytes = read_text_file(pack_path, kMaxPackBytes);
  if (!bytes) return Unexpected{pack_path.string() + ": " + bytes.error()};
  Expected<PackSummary> summary = decode_pack(*bytes);
  if (!summary) return Unexpected{pack_path.string() + ": " + summary.error() + " (nothing was restored)"};
  if (purpose == OpenFor::kComputing) {
    if (summary->unknown_fields)
      return Unexpected{pack_path.string() + ": " + *summary->unknown_fields + " (nothing was restored)"};
    if (const std::optional<std::string> refusal = arithmetic_refusal(summary->arithmetic_digest))
      return Unexpected{pack_path.string() + ": " + *refusal + " (nothing was restored)"};
  }

  // the files in a fresh directory beside the destination, then one rename: the run appears whole or not at all
  std::error_code ec;
  const fs::path parent = dir->parent_path();
  fs::create_directories(parent, ec);
  if (ec) return Unexpected{parent.string() + ": cannot create: " + ec.message()};
  const fs::path staging = parent / ("." + dir->filename().string() + ".restoring-" + std::to_string(::getpid()));
  fs::remove_all(staging, ec);
  if (!fs::create_directory(staging, ec))
    return Unexpected{staging.string() + ": cannot create: " + (ec ? ec.message() : "it exists")};
  auto fail = [&](std::string message) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    return Unexpected{std::move(message)};
  };
  for (const PackEntry& e : summary->entries)
    if (auto error = write_file_atomically(staging / e.name, e.content))
      return fail((staging / e.name).string() + ": " + *error);
  sync_directory(staging);
  // rename(2) replaces an empty directory and fails on one that is not: a file written into the destination
  // since the check above is never overwritten
  if (std::rename(staging.c_str(), dir->c_str()) != 0)
    return fail(run_dir.string() +
                ": cannot move the restored run into place: " + std::generic_category().message(errno));
  sync_directory(parent);
  return summary;
}

}  // namespace poet
