// Tests run_directory/files/run_pack.cpp: a packed run restored elsewhere goes on to write byte for byte the files of
// a run that never moved; a pack of other arithmetic is refused for computing; the pack holds the last checkpoint's
// history even when the logs ran ahead of it; every damaged, truncated, extended or foreign pack is refused with its
// reason and writes nothing; and a restore never writes into a directory that holds anything.

#include "run_directory/files/run_pack.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "../../engine/engine_test_support.h"
#include "common/plumbing/text_file.h"
#include "common/program/build_fingerprint.h"
#include "coordinator/evaluator/local_evaluator.h"
#include "engine/engine.h"
#include "pack_with_checkpoint.h"
#include "run_directory/files/checkpoint_file.h"
#include "run_directory/files/run_directory.h"
#include "run_directory/files/wall_times.h"
#include "run_files.h"
#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
using testing::pack_with_checkpoint;
using testing::run_files;

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

constexpr int kIterations = 6;

class RunPackTest : public ::testing::Test {
 protected:
  // A real run (small_real_run) in dir, from its start or its checkpoint, to iteration `until`, saving each.
  void run_to(const fs::path& dir, int until) {
    pb::RunConfig config = testing::small_real_run();
    config.set_iterations(kIterations);
    const std::optional<std::string> error = testing::run_in_directory(dir, config, until);
    ASSERT_FALSE(error) << *error;
  }

  // A copy of the reference pack of a run stopped at iteration 3.
  std::string pack_at_3() {
    run_to(root_ / "B", 3);
    const Expected<PackSummary> packed = write_run_pack(root_ / "B", pack_);
    EXPECT_TRUE(packed) << packed.error();
    return read(pack_);
  }

  testing::ScratchDir scratch_{"poet_run_pack_test"};
  fs::path root_ = scratch_.path();
  fs::path pack_ = root_ / "run.pack";
};

TEST_F(RunPackTest, ARestoredRunGoesOnAsIfItNeverMoved) {
  run_to(root_ / "A", kIterations);
  run_to(root_ / "B", 3);
  // the live run's logs run ahead of its checkpoint: an iteration appended, not yet saved
  {
    Expected<std::pair<RunDirectory, RunState>> live = RunDirectory::resume(root_ / "B");
    ASSERT_TRUE(live) << live.error();
    LocalEvaluator evaluator(1);
    live->first.append(run_iteration(live->second, evaluator));
  }
  ASSERT_GT(read(root_ / "B" / kStatsFile).size(), read(root_ / "A" / kStatsFile).size() / 2);
  std::ofstream(root_ / "B" / kWallTimesFile) << "iteration,wall_s\n0,1.000\n1,2.000\n2,3.500\n3,4.000\n";

  const Expected<PackSummary> packed = write_run_pack(root_ / "B", pack_);
  ASSERT_TRUE(packed) << packed.error();
  EXPECT_EQ(packed->next_iteration, 3);
  std::vector<std::string> names;
  for (const PackEntry& e : packed->entries) names.push_back(e.name);
  EXPECT_EQ(names, (std::vector<std::string>{kCheckpointFile, kEventsFile, kStatsFile, kWallTimesFile}))
      << "nothing derived";
  EXPECT_EQ(packed->entries[3].content, std::string(kWallTimesHeader) + "0,1.000\n1,2.000\n2,3.500\n")
      << "the wall times of the iterations the checkpoint has seen";

  const Expected<PackSummary> restored = restore_run_pack(pack_, root_ / "moved" / "C");
  ASSERT_TRUE(restored) << restored.error();
  EXPECT_EQ(read(root_ / "moved" / "C" / kWallTimesFile), packed->entries[3].content);
  run_to(root_ / "moved" / "C", kIterations);
  const auto a = run_files(root_ / "A");
  const auto c = run_files(root_ / "moved" / "C");
  ASSERT_GE(a.size(), 10u);
  EXPECT_EQ(a.size(), c.size());
  for (const auto& [name, content] : a) {
    ASSERT_TRUE(c.count(name)) << name << " missing in the moved run";
    EXPECT_TRUE(c.at(name) == content) << name << " differs";
  }
  for (const auto& entry : fs::directory_iterator(root_ / "moved"))
    EXPECT_EQ(entry.path().filename(), "C") << "a staging directory was left behind";
}

TEST_F(RunPackTest, EveryDamagedByteIsRefusedAndNothingIsWritten) {
  const std::string good = pack_at_3();
  ASSERT_TRUE(decode_pack(good));
  // every byte of the frame (header, names, sizes) and a spread of content bytes
  std::vector<size_t> positions;
  for (size_t i = 0; i < std::min<size_t>(good.size(), 200); ++i) positions.push_back(i);
  for (size_t i = 200; i < good.size(); i += good.size() / 300 + 1) positions.push_back(i);
  positions.push_back(good.size() - 1);
  for (size_t i : positions) {
    std::string bad = good;
    bad[i] = static_cast<char>(bad[i] ^ 0x5a);
    std::ofstream(pack_, std::ios::binary | std::ios::trunc) << bad;
    const Expected<PackSummary> restored = restore_run_pack(pack_, root_ / "D");
    ASSERT_FALSE(restored) << "byte " << i << " flipped was not noticed";
    EXPECT_TRUE(contains(restored.error(), pack_.string())) << restored.error();
    ASSERT_FALSE(fs::exists(root_ / "D")) << "byte " << i << ": a refused pack wrote something";
  }
}

TEST_F(RunPackTest, TruncatedExtendedAndForeignFilesAreClearErrors) {
  const std::string good = pack_at_3();
  for (size_t size :
       {size_t{0}, size_t{5}, size_t{14}, size_t{40}, good.size() / 2, good.size() - 5, good.size() - 1}) {
    const Expected<PackSummary> cut = decode_pack(std::string_view(good).substr(0, size));
    ASSERT_FALSE(cut) << size;
    EXPECT_TRUE(contains(cut.error(), size < 8 ? "not a run pack" : "truncated")) << size << ": " << cut.error();
  }
  const Expected<PackSummary> extended = decode_pack(good + "tail");
  ASSERT_FALSE(extended);
  EXPECT_TRUE(contains(extended.error(), "truncated or extended")) << extended.error();
  const Expected<PackSummary> foreign = decode_pack(read(root_ / "B" / kCheckpointFile));
  ASSERT_FALSE(foreign);
  EXPECT_TRUE(contains(foreign.error(), "not a run pack")) << foreign.error();
  std::string newer = good;
  newer[8] = 9;  // the format version
  EXPECT_TRUE(contains(decode_pack(newer).error(), "format version 9")) << decode_pack(newer).error();
}

// With CURVE, the keys of workers refused for wrong results go with the run, so that they stay refused where it
// goes on; only the lines that are keys are packed, and a pack whose keys entry holds anything else is refused.
TEST_F(RunPackTest, TheRefusedKeysTravelWithTheRun) {
  run_to(root_ / "B", 3);
  const std::string key = "rq:rM>}U?@Lns47E1%kR.o@n%FcmmsL/@{H8]yf7";  // the ZeroMQ guide's example public key
  std::ofstream(root_ / "B" / kRefusedKeysFile) << key << "\nnot a key\n";
  const Expected<PackSummary> packed = write_run_pack(root_ / "B", pack_);
  ASSERT_TRUE(packed) << packed.error();
  ASSERT_EQ(packed->entries.back().name, kRefusedKeysFile);
  EXPECT_EQ(packed->entries.back().content, key + "\n");
  const Expected<PackSummary> restored = restore_run_pack(pack_, root_ / "C");
  ASSERT_TRUE(restored) << restored.error();
  EXPECT_EQ(read(root_ / "C" / kRefusedKeysFile), key + "\n");

  std::vector<PackEntry> entries = packed->entries;
  entries.back().content += "../../etc/passwd\n";
  EXPECT_TRUE(contains(decode_pack(encode_pack(entries)).error(), "not a CURVE public key"));
}

TEST_F(RunPackTest, PacksWhoseEntriesLieAreRefused) {
  pack_at_3();
  std::vector<PackEntry> entries = decode_pack(read(pack_)).value().entries;
  // an unknown file (a path outside the run directory)
  std::vector<PackEntry> escaping = entries;
  escaping.push_back({"../../etc/passwd", "x"});
  EXPECT_TRUE(contains(decode_pack(encode_pack(escaping)).error(), "is not a file of a run pack"));
  // a file twice
  std::vector<PackEntry> twice = entries;
  twice.push_back(entries[1]);
  EXPECT_TRUE(contains(decode_pack(encode_pack(twice)).error(), "comes twice"));
  // no checkpoint
  std::vector<PackEntry> headless(entries.begin() + 1, entries.end());
  EXPECT_TRUE(contains(decode_pack(encode_pack(headless)).error(), "no checkpoint.pb"));
  // a log other than the one the checkpoint saw (same size, one byte changed), and a shorter one
  std::vector<PackEntry> changed = entries;
  changed[2].content[changed[2].content.size() - 2] ^= 1;
  EXPECT_TRUE(contains(decode_pack(encode_pack(changed)).error(), "differ from those the checkpoint has seen"));
  std::vector<PackEntry> shorter = entries;
  shorter[1].content.pop_back();
  EXPECT_TRUE(contains(decode_pack(encode_pack(shorter)).error(), "but the checkpoint records"));
  // wall times of iterations the checkpoint has not seen
  std::vector<PackEntry> ahead = entries;
  ahead.push_back({kWallTimesFile, "iteration,wall_s\n7,1.000\n"});
  EXPECT_TRUE(contains(decode_pack(encode_pack(ahead)).error(), "which the checkpoint has not seen"));
}

TEST_F(RunPackTest, ARestoreNeverWritesIntoADirectoryThatHoldsAnything) {
  pack_at_3();
  // a run directory (B itself), a directory with any file, a file: refused, untouched
  const auto before = run_files(root_ / "B");
  const Expected<PackSummary> over_run = restore_run_pack(pack_, root_ / "B");
  ASSERT_FALSE(over_run);
  EXPECT_TRUE(contains(over_run.error(), "never overwritten")) << over_run.error();
  EXPECT_EQ(run_files(root_ / "B"), before);
  fs::create_directories(root_ / "E");
  std::ofstream(root_ / "E" / "notes.txt") << "mine";
  ASSERT_FALSE(restore_run_pack(pack_, root_ / "E"));
  EXPECT_EQ(read(root_ / "E" / "notes.txt"), "mine");
  EXPECT_EQ(std::distance(fs::directory_iterator(root_ / "E"), fs::directory_iterator()), 1);
  std::ofstream(root_ / "F") << "a file";
  ASSERT_FALSE(restore_run_pack(pack_, root_ / "F"));
  EXPECT_EQ(read(root_ / "F"), "a file");
  // an empty directory is taken, and so is one given with a trailing separator
  fs::create_directories(root_ / "G");
  const Expected<PackSummary> into_empty = restore_run_pack(pack_, (root_ / "G").string() + "/");
  ASSERT_TRUE(into_empty) << into_empty.error();
  EXPECT_TRUE(fs::exists(root_ / "G" / kCheckpointFile));
  EXPECT_EQ(read(root_ / "G" / kCheckpointFile), read(root_ / "B" / kCheckpointFile));
}

TEST_F(RunPackTest, PackingAChangedOrMissingRunIsAClearError) {
  const Expected<PackSummary> none = write_run_pack(root_ / "nothing", pack_);
  ASSERT_FALSE(none);
  EXPECT_TRUE(contains(none.error(), "no such directory")) << none.error();
  run_to(root_ / "B", 2);
  // a pack in the run directory, even over its checkpoint: refused, nothing changed
  const std::string checkpoint = read(root_ / "B" / kCheckpointFile);
  const Expected<PackSummary> inside = write_run_pack(root_ / "B", root_ / "B" / kCheckpointFile);
  ASSERT_FALSE(inside);
  EXPECT_TRUE(contains(inside.error(), "inside the run directory")) << inside.error();
  EXPECT_EQ(read(root_ / "B" / kCheckpointFile), checkpoint);
  std::string stats = read(root_ / "B" / kStatsFile);
  stats[stats.size() - 3] = stats[stats.size() - 3] == '1' ? '2' : '1';
  std::ofstream(root_ / "B" / kStatsFile, std::ios::binary | std::ios::trunc) << stats;
  const Expected<PackSummary> changed = write_run_pack(root_ / "B", pack_);
  ASSERT_FALSE(changed);
  EXPECT_TRUE(contains(changed.error(), "CRC-32 mismatch")) << changed.error();
  EXPECT_FALSE(fs::exists(pack_)) << "no pack of a run whose history changed";

  // wall times that cannot be read are not left out unsaid: a symbolic-link loop in their place is an error
  run_to(root_ / "D", 2);
  fs::remove(root_ / "D" / kWallTimesFile);
  fs::create_symlink(root_ / "D" / "loop", root_ / "D" / kWallTimesFile);
  fs::create_symlink(root_ / "D" / kWallTimesFile, root_ / "D" / "loop");
  const Expected<PackSummary> looped = write_run_pack(root_ / "D", pack_);
  ASSERT_FALSE(looped);
  EXPECT_TRUE(contains(looped.error(), std::string(kWallTimesFile) + ": cannot access")) << looped.error();
  EXPECT_FALSE(fs::exists(pack_));
}

}  // namespace
}  // namespace poet

namespace poet {
namespace {

// A checkpoint records the arithmetic of the process that wrote it; a pack written before the project computed its
// own math (no digest), or by a machine that computes differently, is refused for computing before anything is
// written, and a restored run directory likewise; for reading (poetctl unpack) both are restored and opened.
TEST_F(RunPackTest, APackOfOtherArithmeticIsRefusedForComputingAndRestoredForReading) {
  const std::string pack = pack_at_3();
  Expected<PackSummary> decoded = decode_pack(pack);
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->arithmetic_digest, std::optional<uint64_t>(arithmetic_digest()));
  struct Case {
    const char* name;
    std::function<void(pb::Checkpoint&)> change;
    const char* says;
  };
  const Case cases[] = {
      {"before", [](pb::Checkpoint& c) { c.clear_arithmetic_digest(); },
       "written by a build before the project computed its own exp, log, sin and cos"},
      {"other", [](pb::Checkpoint& c) { c.set_arithmetic_digest(c.arithmetic_digest() ^ 1); },
       "this machine computes differently from the one that wrote the checkpoint"},
  };
  for (const Case& c : cases) {
    const fs::path file = root_ / (std::string(c.name) + ".pack");
    std::ofstream(file, std::ios::binary) << pack_with_checkpoint(pack, c.change);
    const Expected<PackSummary> refused = restore_run_pack(file, root_ / c.name);
    ASSERT_FALSE(refused) << c.name;
    EXPECT_TRUE(contains(refused.error(), c.says)) << refused.error();
    EXPECT_TRUE(contains(refused.error(), "(nothing was restored)")) << refused.error();
    EXPECT_FALSE(fs::exists(root_ / c.name));

    const Expected<PackSummary> read_only = restore_run_pack(file, root_ / c.name, OpenFor::kReading);
    ASSERT_TRUE(read_only) << read_only.error();
    const auto resumed = RunDirectory::resume(root_ / c.name);
    ASSERT_FALSE(resumed) << c.name;
    EXPECT_TRUE(contains(resumed.error(), c.says)) << resumed.error();
    EXPECT_TRUE(RunDirectory::resume(root_ / c.name, OpenFor::kReading)) << c.name;
  }
}

}  // namespace
}  // namespace poet
