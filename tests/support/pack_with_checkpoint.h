#pragma once
// A pack's bytes with its checkpoint changed by a function (the entry re-encoded, the logs as they were): how the
// tests make a pack of another writer, version or arithmetic from one of this build.

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "run_directory/files/checkpoint_file.h"
#include "run_directory/files/run_directory.h"
#include "run_directory/files/run_pack.h"

namespace poet::testing {

inline std::string pack_with_checkpoint(const std::string& pack, const std::function<void(pb::Checkpoint&)>& change) {
  Expected<PackSummary> decoded = decode_pack(pack);
  EXPECT_TRUE(decoded) << decoded.error();
  if (!decoded) return pack;
  for (PackEntry& entry : decoded->entries) {
    if (entry.name != kCheckpointFile) continue;
    Expected<pb::Checkpoint> checkpoint = decode_checkpoint_file(entry.content);
    EXPECT_TRUE(checkpoint) << checkpoint.error();
    if (!checkpoint) return pack;
    change(*checkpoint);
    entry.content = encode_checkpoint_file(*checkpoint);
  }
  return encode_pack(decoded->entries);
}

}  // namespace poet::testing
