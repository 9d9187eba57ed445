// Tests run_directory/files/wall_times.cpp: the clock continues across processes from the lines the checkpoint has
// seen, later lines are dropped, and a damaged line is named and costs only the times from it on.

#include "run_directory/files/wall_times.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "scratch_dir.h"

namespace poet {
namespace {

namespace fs = std::filesystem;

class WallTimesTest : public ::testing::Test {
 protected:
  std::string text() const {
    std::ifstream in(dir_ / kWallTimesFile);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  void write(const std::string& text) const { std::ofstream(dir_ / kWallTimesFile) << text; }

  poet::testing::ScratchDir scratch_;
  fs::path dir_ = scratch_.path();
};

TEST_F(WallTimesTest, ANewRunStartsTheClockAtZero) {
  std::string warning;
  WallTimes w = WallTimes::open(dir_, 0, &warning);
  EXPECT_EQ(warning, "");
  EXPECT_EQ(w.carried(), 0);
  EXPECT_FALSE(w.record(0, 1.5, {0, 1.0, 0.25, 0}, 1.125));
  EXPECT_FALSE(w.record(1, 3.25, {0.125, 1.0, 0.25, 0.5}, 1.5));
  EXPECT_EQ(text(), std::string(kWallTimesHeader) +
                        "0,1.500,0.000,1.000,0.250,0.000,1.125\n1,3.250,0.125,1.000,0.250,0.500,1.500\n");
  const Expected<std::vector<WallTime>> lines = parse_wall_times(text());
  ASSERT_TRUE(lines) << lines.error();
  ASSERT_TRUE((*lines)[1].phases);
  EXPECT_EQ(*(*lines)[1].phases, (PhaseSeconds{0.125, 1.0, 0.25, 0.5}));
  EXPECT_EQ((*lines)[1].waiting, 1.5);
}

TEST_F(WallTimesTest, AResumeKeepsTheCheckpointsLinesAndContinuesTheClock) {
  write("iteration,wall_s\n0,1.000\n1,2.000\n2,3.000\n3,4.000\n");
  std::string warning;
  WallTimes w = WallTimes::open(dir_, 2, &warning);  // the checkpoint has seen iterations 0 and 1
  EXPECT_EQ(warning, "");
  EXPECT_EQ(w.carried(), 2.0);
  EXPECT_FALSE(w.record(2, 0.5, {0, 0.25, 0.125, 0}, 0.25));
  // an earlier build's file: its lines keep their two fields under the full header
  EXPECT_EQ(text(), std::string(kWallTimesHeader) + "0,1.000\n1,2.000\n2,2.500,0.000,0.250,0.125,0.000,0.250\n");
  const Expected<std::vector<WallTime>> lines = parse_wall_times(text());
  ASSERT_TRUE(lines) << lines.error();
  ASSERT_EQ(lines->size(), 3u);
  EXPECT_EQ((*lines)[2].iteration, 2);
  EXPECT_DOUBLE_EQ((*lines)[2].seconds, 2.5);
  EXPECT_FALSE((*lines)[1].phases);
}

// A file of the build before waiting_s: its lines keep their six fields under the full header.
TEST_F(WallTimesTest, LinesWithoutWaitingKeepTheirFields) {
  write(std::string(kWallTimesHeaderWithoutWaiting) + "0,1.000,0.000,0.500,0.250,0.000\n");
  std::string warning;
  WallTimes w = WallTimes::open(dir_, 1, &warning);
  EXPECT_EQ(warning, "");
  EXPECT_FALSE(w.record(1, 1.0, {0, 0.5, 0.25, 0}, 0.5));
  EXPECT_EQ(text(),
            std::string(kWallTimesHeader) + "0,1.000,0.000,0.500,0.250,0.000\n1,2.000,0.000,0.500,0.250,0.000,0.500\n");
  const Expected<std::vector<WallTime>> lines = parse_wall_times(text());
  ASSERT_TRUE(lines) << lines.error();
  EXPECT_TRUE((*lines)[0].phases && !(*lines)[0].waiting);
  EXPECT_TRUE((*lines)[1].phases && (*lines)[1].waiting);
}

// A crash in the middle of an append leaves a line without its newline: it is dropped, the whole lines kept.
TEST_F(WallTimesTest, ALineCutByACrashIsDropped) {
  write("iteration,wall_s\n0,1.000\n1,2.0");
  std::string warning;
  WallTimes w = WallTimes::open(dir_, 5, &warning);
  EXPECT_EQ(warning, "");
  EXPECT_EQ(w.carried(), 1.0);
  EXPECT_EQ(text(), std::string(kWallTimesHeader) + "0,1.000\n");
}

// A damaged line is named; the lines before it (those the checkpoint has seen) are kept and the clock goes on.
TEST_F(WallTimesTest, ADamagedLineIsNamedAndTheLinesBeforeItAreKept) {
  write("iteration,wall_s\n0,1.000\n1,2.000\n2,x\n3,4.000\n");
  std::string warning;
  WallTimes w = WallTimes::open(dir_, 5, &warning);
  EXPECT_NE(warning.find(kWallTimesFile), std::string::npos) << warning;
  EXPECT_NE(warning.find("line 4"), std::string::npos) << warning;
  EXPECT_NE(warning.find("the clock goes on from iteration 1"), std::string::npos) << warning;
  EXPECT_EQ(w.carried(), 2.0);
  EXPECT_EQ(text(), std::string(kWallTimesHeader) + "0,1.000\n1,2.000\n");
}

// With no good line before the damage (here the header), the times are lost and the clock restarts.
TEST_F(WallTimesTest, ADamagedHeaderIsNamedAndTheClockRestarts) {
  write("iteration;wall_s\n0,1.000\n");
  std::string warning;
  WallTimes w = WallTimes::open(dir_, 5, &warning);
  EXPECT_NE(warning.find("line 1"), std::string::npos) << warning;
  EXPECT_NE(warning.find("its clock restarts"), std::string::npos) << warning;
  EXPECT_EQ(w.carried(), 0);
  EXPECT_EQ(text(), kWallTimesHeader);
}

// A file that cannot be reached (a symbolic-link loop) is neither read as absent nor replaced: nothing is recorded.
TEST_F(WallTimesTest, AFileThatCannotBeReachedIsNamedAndLeftAlone) {
  const fs::path path = dir_ / kWallTimesFile;
  fs::create_symlink(dir_ / "loop", path);
  fs::create_symlink(path, dir_ / "loop");
  std::string warning;
  WallTimes w = WallTimes::open(dir_, 5, &warning);
  EXPECT_NE(warning.find("cannot access"), std::string::npos) << warning;
  EXPECT_NE(warning.find("wall times are not recorded"), std::string::npos) << warning;
  EXPECT_FALSE(w.record(5, 1.0, {}, 0));
  EXPECT_TRUE(fs::is_symlink(path)) << "the link was replaced";
}

TEST(ParseWallTimes, RefusesWhatTheWriterNeverWrites) {
  const std::pair<const char*, const char*> cases[] = {
      {"", "no header"},
      {"iteration,seconds\n", "line 1"},
      {"iteration,wall_s\n0,1.0", "cut short"},
      {"iteration,wall_s\n0\n", "expected iteration,wall_s"},
      {"iteration,wall_s\n-1,1.0\n", "non-negative integer"},
      {"iteration,wall_s\n0,nan\n", "finite"},
      {"iteration,wall_s\n0,1e999\n", "finite"},
      {"iteration,wall_s\n0,-2\n", "non-negative"},
      {"iteration,wall_s\n1,1.0\n1,2.0\n", "does not follow"},
      {"iteration,wall_s\n1,3.0\n2,2.0\n", "goes back"},
      {"iteration,wall_s\n1,3.0,0,0,0,0\n", "expected iteration,wall_s"},  // phases under the old header
      {"iteration,wall_s,reproduction_s,es_steps_s,evaluations_s,transfer_s\n1,3.0,0,0,0\n",
       "or every phase's seconds"},
      {"iteration,wall_s,reproduction_s,es_steps_s,evaluations_s,transfer_s\n1,3.0,0,0,-1,0\n", "field 5"},
      {"iteration,wall_s,reproduction_s,es_steps_s,evaluations_s,transfer_s\n1,3.0,0,0,0,nan\n", "field 6"},
      {"iteration,wall_s,reproduction_s,es_steps_s,evaluations_s,transfer_s\n1,3.0,0,0,0,0,1\n",
       "or every phase's seconds"},  // waiting under the header without it
      {"iteration,wall_s,reproduction_s,es_steps_s,evaluations_s,transfer_s,waiting_s\n1,3.0,0,0,0,0,-1\n",
       "waiting_s"},
      {"iteration,wall_s,reproduction_s,es_steps_s,evaluations_s,transfer_s,waiting_s\n1,3.0,0,0,0,0,0,0\n",
       "or waiting_s too"},
  };
  for (const auto& [text, expected] : cases) {
    const Expected<std::vector<WallTime>> lines = parse_wall_times(text);
    ASSERT_FALSE(lines) << text;
    EXPECT_NE(lines.error().find(expected), std::string::npos) << text << " → " << lines.error();
  }
}

}  // namespace
}  // namespace poet
