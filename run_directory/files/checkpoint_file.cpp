#include "run_directory/files/checkpoint_file.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include "common/plumbing/text_file.h"
#include "common/text/text_format.h"
#include "run_directory/files/crc32.h"
#include "run_directory/files/little_endian.h"

namespace poet {

std::string encode_checkpoint_file(const pb::Checkpoint& checkpoint) {
  std::string body;
  {
    // deterministic: map fields (none today) and unknown fields would otherwise make equal states differ
    google::protobuf::io::StringOutputStream stream(&body);
    google::protobuf::io::CodedOutputStream coded(&stream);
    coded.SetSerializationDeterministic(true);
    checkpoint.SerializeToCodedStream(&coded);
  }
  std::string out;
  out.reserve(kCheckpointHeaderBytes + body.size());
  out.append(kCheckpointMagic);
  put_le(out, kCheckpointFormatVersion, 4);
  put_le(out, body.size(), 8);
  put_le(out, crc32_extend(0, body), 4);
  out.append(body);
  return out;
}

Expected<pb::Checkpoint> decode_checkpoint_file(std::string_view bytes) {
  if (bytes.size() < kCheckpointHeaderBytes)
    return Unexpected{"not a checkpoint: " + std::to_string(bytes.size()) + " bytes, shorter than the " +
                      std::to_string(kCheckpointHeaderBytes) + "-byte header (truncated?)"};
  if (bytes.substr(0, kCheckpointMagic.size()) != kCheckpointMagic)
    return Unexpected{"not a checkpoint: the file does not start with \"POETCKPT\" (corrupt, or not a checkpoint)"};
  const uint64_t version = get_le(bytes, 8, 4);
  if (version != kCheckpointFormatVersion)
    return Unexpected{"checkpoint format version " + std::to_string(version) + "; this build reads version " +
                      std::to_string(kCheckpointFormatVersion)};
  const uint64_t length = get_le(bytes, 12, 8);
  const uint64_t present = bytes.size() - kCheckpointHeaderBytes;
  if (length != present)
    return Unexpected{"the header gives a body of " + std::to_string(length) + " bytes, the file holds " +
                      std::to_string(present) + (length > present ? " (truncated)" : " (corrupt)")};
  const std::string_view body = bytes.substr(kCheckpointHeaderBytes);
  const uint32_t expected = static_cast<uint32_t>(get_le(bytes, 20, 4));
  const uint32_t actual = crc32_extend(0, body);
  if (expected != actual)
    return Unexpected{"checksum mismatch: the header records CRC-32 " + hex_text(expected, 8) + ", the body has " +
                      hex_text(actual, 8) + " (the file is corrupt)"};
  pb::Checkpoint checkpoint;
  if (!checkpoint.ParseFromArray(body.data(), static_cast<int>(body.size())))
    return Unexpected{"the body is not a valid checkpoint message"};
  return checkpoint;
}

Expected<pb::Checkpoint> read_checkpoint_file(const std::filesystem::path& path) {
  Expected<std::string> bytes = read_text_file(path, kMaxCheckpointBytes);
  if (!bytes) return Unexpected{path.string() + ": " + bytes.error()};
  Expected<pb::Checkpoint> checkpoint = decode_checkpoint_file(*bytes);
  if (!checkpoint) return Unexpected{path.string() + ": " + checkpoint.error()};
  return checkpoint;
}

}  // namespace poet
