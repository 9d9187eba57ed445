// Tests run_directory/files/checkpoint_file.cpp: the header and checksum turn every flipped byte, truncation and
// foreign file into a clear error, and a good file decodes to the message that was written.

#include "run_directory/files/checkpoint_file.h"

#include <gtest/gtest.h>

#include <string>

#include "engine/engine.h"
#include "run_directory/config/run_config.h"
#include "run_directory/files/checkpoint.h"

namespace poet {
namespace {

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

pb::Checkpoint sample() {
  pb::RunConfig config;
  config.set_seed(11);
  config.set_iterations(3);
  return to_checkpoint(config, initial_state(run_settings(config)));
}

TEST(CheckpointFile, RoundTripsTheMessage) {
  const pb::Checkpoint message = sample();
  const std::string bytes = encode_checkpoint_file(message);
  ASSERT_GT(bytes.size(), kCheckpointHeaderBytes);
  EXPECT_EQ(bytes.substr(0, 8), "POETCKPT");
  const Expected<pb::Checkpoint> decoded = decode_checkpoint_file(bytes);
  ASSERT_TRUE(decoded) << decoded.error();
  EXPECT_EQ(decoded->SerializeAsString(), message.SerializeAsString());
  EXPECT_EQ(encode_checkpoint_file(*decoded), bytes);  // equal states, equal bytes
}

// Protobuf alone took 12 of 12 flipped bytes as valid messages; with the header every flip is an error.
TEST(CheckpointFile, EveryFlippedByteIsDetected) {
  const std::string good = encode_checkpoint_file(sample());
  std::vector<size_t> positions;
  for (size_t i = 0; i < kCheckpointHeaderBytes; ++i) positions.push_back(i);
  for (size_t i = kCheckpointHeaderBytes; i < good.size(); i += good.size() / 97) positions.push_back(i);
  positions.push_back(good.size() - 1);
  for (size_t i : positions) {
    for (unsigned char mask : {0x01, 0x80, 0xff}) {
      std::string bad = good;
      bad[i] = static_cast<char>(bad[i] ^ mask);
      const Expected<pb::Checkpoint> decoded = decode_checkpoint_file(bad);
      EXPECT_FALSE(decoded) << "byte " << i << " ^ " << int(mask) << " was accepted";
    }
  }
  std::string body_flip = good;
  body_flip[good.size() / 2] ^= 0x04;
  EXPECT_TRUE(contains(decode_checkpoint_file(body_flip).error(), "checksum mismatch"));
}

TEST(CheckpointFile, TruncatedExtendedAndForeignFilesAreClearErrors) {
  const std::string good = encode_checkpoint_file(sample());
  EXPECT_TRUE(contains(decode_checkpoint_file("").error(), "shorter than the 24-byte header"));
  EXPECT_TRUE(contains(decode_checkpoint_file(good.substr(0, 10)).error(), "shorter than the 24-byte header"));
  EXPECT_TRUE(contains(decode_checkpoint_file(good.substr(0, good.size() - 1)).error(), "(truncated)"));
  EXPECT_TRUE(contains(decode_checkpoint_file(good + "x").error(), "(corrupt)"));
  EXPECT_TRUE(contains(decode_checkpoint_file(sample().SerializeAsString()).error(), "does not start with"));

  std::string newer = good;
  newer[8] = 2;  // format version 2
  EXPECT_TRUE(
      contains(decode_checkpoint_file(newer).error(), "checkpoint format version 2; this build reads version 1"));
}

TEST(CheckpointFile, ReadingNamesTheFile) {
  const Expected<pb::Checkpoint> missing = read_checkpoint_file("/nonexistent/checkpoint.pb");
  ASSERT_FALSE(missing);
  EXPECT_TRUE(contains(missing.error(), "/nonexistent/checkpoint.pb: ")) << missing.error();
}

}  // namespace
}  // namespace poet
