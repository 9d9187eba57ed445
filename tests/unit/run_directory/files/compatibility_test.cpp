// Tests what docs/compatibility.md promises of run files across versions (run_pack.cpp, run_directory.cpp,
// checkpoint.cpp): every pack committed under tests/data/compat/<version>/ by an earlier release restores and resumes
// to the files of a run that never stopped; a pack or checkpoint of another format version, or a checkpoint holding
// fields this build does not know (a later build's), is refused for computing with a message naming both versions,
// and nothing is restored.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "../../engine/engine_test_support.h"
#include "common/program/command_line.h"
#include "coordinator/evaluator/local_evaluator.h"
#include "engine/engine.h"
#include "pack_with_checkpoint.h"
#include "run_directory/config/run_config.h"
#include "run_directory/files/checkpoint.h"
#include "run_directory/files/checkpoint_file.h"
#include "run_directory/files/run_directory.h"
#include "run_directory/files/run_pack.h"
#include "run_directory/files/wall_times.h"
#include "run_files.h"
#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;
using testing::pack_with_checkpoint;
using testing::run_files;

const fs::path kCompatDir = fs::path(POET_SOURCE_DIR) / "tests" / "data" / "compat";

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }

// The versions that committed a pack (tests/data/compat/README.md), oldest first.
std::vector<fs::path> committed_versions() {
  std::vector<fs::path> dirs;
  for (const auto& entry : fs::directory_iterator(kCompatDir))
    if (entry.is_directory()) dirs.push_back(entry.path());
  std::sort(dirs.begin(), dirs.end());
  return dirs;
}

// Resumes the run in dir as poet-coordinator --resume --iterations N does, and runs it to its end.
std::optional<std::string> resume_to(const fs::path& dir, int iterations) {
  Expected<std::pair<RunDirectory, RunState>> resumed = RunDirectory::resume(dir);
  if (!resumed) return resumed.error();
  auto& [run, state] = *resumed;
  pb::RunConfig config = run.config();
  config.set_iterations(iterations);
  state.settings = run_settings(config);
  if (auto error = run.write_config(config)) return error;
  if (auto error = run.save(state)) return error;
  LocalEvaluator evaluator(2);
  while (!run_complete(state)) {
    run.append(run_iteration(state, evaluator));
    if (auto error = run.save(state)) return error;
  }
  return std::nullopt;
}

// What a later build may add: a field of the checkpoint and one of a pair that this build's schema lacks.
void add_later_fields(pb::Checkpoint& checkpoint) {
  checkpoint.GetReflection()->MutableUnknownFields(&checkpoint)->AddVarint(1000, 1);
  pb::PairState* pair = checkpoint.mutable_pairs(0);
  pair->GetReflection()->MutableUnknownFields(pair)->AddFixed64(99, 7);
}

class CompatibilityTest : public ::testing::Test {
 protected:
  testing::ScratchDir scratch_{"poet_compatibility_test"};
  fs::path root_ = scratch_.path();
};

// Each committed pack, written by its version's poet-coordinator and poetctl pack, restores and resumes here, and
// goes on to write byte for byte the files of the same config run here from the start (while the golden digests
// stand: a release that moves them says so in CHANGELOG.md, and its older packs then resume without this equality).
TEST_F(CompatibilityTest, EveryCommittedPackResumesToTheRunThatNeverStopped) {
  const std::vector<fs::path> versions = committed_versions();
  ASSERT_FALSE(versions.empty()) << "no pack under " << kCompatDir;
  for (const fs::path& version : versions) {
    SCOPED_TRACE(version.filename().string());
    const Expected<pb::RunConfig> config = load_run_config((version / "config.textproto").string());
    ASSERT_TRUE(config) << config.error();
    const Expected<PackSummary> restored = restore_run_pack(version / "run.pack", root_ / "moved");
    ASSERT_TRUE(restored) << restored.error();
    const Expected<pb::Checkpoint> checkpoint = read_checkpoint_file(root_ / "moved" / kCheckpointFile);
    ASSERT_TRUE(checkpoint) << checkpoint.error();
    EXPECT_EQ(checkpoint->written_by(), version.filename().string()) << "the pack's folder names its version";
    ASSERT_LT(restored->next_iteration, config->iterations()) << "the pack holds a run stopped before its end";

    const std::optional<std::string> resumed = resume_to(root_ / "moved", config->iterations());
    ASSERT_FALSE(resumed) << *resumed;
    ASSERT_FALSE(testing::run_in_directory(root_ / "straight", *config, config->iterations()));
    const auto moved = run_files(root_ / "moved");
    const auto straight = run_files(root_ / "straight");
    EXPECT_EQ(moved.size(), straight.size());
    for (const auto& [name, content] : straight) {
      ASSERT_TRUE(moved.count(name)) << name << " missing in the resumed run";
      EXPECT_TRUE(moved.at(name) == content) << name << " differs";
    }
    fs::remove_all(root_ / "moved");
    fs::remove_all(root_ / "straight");
  }
}

// A pack or a checkpoint whose header gives another format version, older or newer, is refused before anything
// is read or written, and the message gives both versions.
TEST_F(CompatibilityTest, AnotherFormatVersionIsRefusedNamingBoth) {
  const std::string pack = read(committed_versions().back() / "run.pack");
  for (const char version : {'\0', '\2', '\x09'}) {
    const std::string number = std::to_string(static_cast<int>(version));
    std::string other = pack;
    other[8] = version;  // the pack's format version (run_pack.h)
    write(root_ / "other.pack", other);
    const Expected<PackSummary> refused = restore_run_pack(root_ / "other.pack", root_ / "P");
    ASSERT_FALSE(refused) << number;
    EXPECT_TRUE(contains(refused.error(), "format version " + number + ", this build reads version " +
                                              std::to_string(kPackFormatVersion)))
        << refused.error();
    EXPECT_TRUE(contains(refused.error(), "(nothing was restored)")) << refused.error();
    EXPECT_FALSE(fs::exists(root_ / "P"));
  }

  ASSERT_TRUE(restore_run_pack(committed_versions().back() / "run.pack", root_ / "R"));
  const fs::path file = root_ / "R" / kCheckpointFile;
  const std::string checkpoint = read(file);
  for (const char version : {'\0', '\2'}) {
    const std::string number = std::to_string(static_cast<int>(version));
    std::string other = checkpoint;
    other[8] = version;  // the checkpoint's format version (checkpoint_file.h), outside its CRC
    write(file, other);
    for (const OpenFor purpose : {OpenFor::kComputing, OpenFor::kReading}) {
      const auto resumed = RunDirectory::resume(root_ / "R", purpose);
      ASSERT_FALSE(resumed) << number;
      EXPECT_TRUE(contains(resumed.error(), file.string() + ": checkpoint format version " + number +
                                                "; this build reads version " +
                                                std::to_string(kCheckpointFormatVersion)))
          << resumed.error();
    }
  }
  write(file, checkpoint);
  EXPECT_TRUE(RunDirectory::resume(root_ / "R")) << "the same bytes with their own version resume";
}

// A checkpoint of the same format version that holds fields this build does not know was written by a later
// build: computing on from it would drop them, so a resume and a restore for computing refuse it, naming the
// fields and both versions; a restore for reading (poetctl unpack) and poet-report's reading still open it.
TEST_F(CompatibilityTest, ACheckpointOfALaterBuildIsRefusedNamingBothVersions) {
  const std::string pack = read(committed_versions().back() / "run.pack");
  const std::string ours = std::string("this build is poet ") + project_version();
  struct Case {
    const char* name;
    std::function<void(pb::Checkpoint&)> change;
    std::string says;
  };
  const Case cases[] = {
      {"named",
       [](pb::Checkpoint& c) {
         add_later_fields(c);
         c.set_written_by("9.1.0");
       },
       "written by poet 9.1.0, " + ours +
           ". Resumed here the run would drop them and go on as another run: go on "
           "with poet 9.1.0 or later"},
      {"unnamed",
       [](pb::Checkpoint& c) {
         add_later_fields(c);
         c.clear_written_by();
       },
       "written by a later build, " + ours},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path file = root_ / (std::string(c.name) + ".pack");
    write(file, pack_with_checkpoint(pack, c.change));
    const Expected<PackSummary> refused = restore_run_pack(file, root_ / c.name);
    ASSERT_FALSE(refused);
    EXPECT_TRUE(contains(refused.error(), "holds fields this build does not know (field 1000, pairs[0] field 99)"))
        << refused.error();
    EXPECT_TRUE(contains(refused.error(), c.says)) << refused.error();
    EXPECT_TRUE(contains(refused.error(), "(nothing was restored)")) << refused.error();
    EXPECT_FALSE(fs::exists(root_ / c.name));

    const Expected<PackSummary> read_only = restore_run_pack(file, root_ / c.name, OpenFor::kReading);
    ASSERT_TRUE(read_only) << read_only.error();
    ASSERT_TRUE(read_only->unknown_fields);
    const auto resumed = RunDirectory::resume(root_ / c.name);
    ASSERT_FALSE(resumed);
    EXPECT_TRUE(contains(resumed.error(), (root_ / c.name / kCheckpointFile).string() + ": the checkpoint holds "))
        << resumed.error();
    EXPECT_TRUE(contains(resumed.error(), c.says)) << resumed.error();
    EXPECT_TRUE(RunDirectory::resume(root_ / c.name, OpenFor::kReading));
  }
}

// Checkpoints of earlier builds lack written_by (and fields added since): they resume, the absent fields read as
// their documented defaults; a save then records this build's version.
TEST_F(CompatibilityTest, ACheckpointWithoutAVersionResumesAndIsStampedOnSave) {
  write(root_ / "older.pack", pack_with_checkpoint(read(committed_versions().back() / "run.pack"),
                                                   [](pb::Checkpoint& c) { c.clear_written_by(); }));
  ASSERT_TRUE(restore_run_pack(root_ / "older.pack", root_ / "O"));
  const std::optional<std::string> resumed = resume_to(root_ / "O", 4);
  ASSERT_FALSE(resumed) << *resumed;
  const Expected<pb::Checkpoint> saved = read_checkpoint_file(root_ / "O" / kCheckpointFile);
  ASSERT_TRUE(saved) << saved.error();
  EXPECT_EQ(saved->written_by(), project_version());
}

}  // namespace
}  // namespace poet
