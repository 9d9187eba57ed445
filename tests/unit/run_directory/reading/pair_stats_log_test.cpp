// Tests run_directory/reading/pair_stats_log.cpp (and log_lines.cpp under it): the strict reading of the rows a
// checkpoint vouches for, with errors naming the line, and the live tail that reads on as the file grows.

#include "run_directory/reading/pair_stats_log.h"

#include <gtest/gtest.h>

#include <fstream>

#include "scratch_dir.h"

namespace poet {
namespace {

constexpr char kHeader[] = "iteration,pair,env,score,finished,best_score,solved,es_steps\n";

TEST(PairStatsLog, StrictReadingGivesEveryRowOrNamesTheBadLine) {
  const std::string rows = std::string(kHeader) + "3,1,\"odd, name\",12.5,true,20,false,7\n4,1,x,13,false,21,true,8\n";
  Expected<std::vector<StatsRow>> read = parse_stats("p.csv", rows);
  ASSERT_TRUE(read) << read.error();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ((*read)[0].iteration, 3);
  EXPECT_EQ((*read)[0].score, 12.5);
  EXPECT_TRUE((*read)[0].finished);
  EXPECT_TRUE((*read)[1].solved);
  EXPECT_EQ((*read)[1].es_steps, 8);
  EXPECT_EQ((*read)[1].run_rollouts, -1);  // a run written before the column existed

  EXPECT_EQ(parse_stats("p.csv", std::string(kHeader) + "3,1,x,nan?,true,20,false,7\n").error(),
            "p.csv:2: score: not a valid value");
  EXPECT_EQ(parse_stats("p.csv", std::string(kHeader) + "3,1\n").error(), "p.csv:2: 2 fields, the header has 8");
  EXPECT_EQ(parse_stats("p.csv", std::string(kHeader) + "3,1").error(),
            "p.csv: the last line recorded by the checkpoint is cut");
  EXPECT_EQ(parse_stats("p.csv", "iteration,pair\n").error(), "p.csv: the header has no column \"score\"");
  EXPECT_EQ(parse_stats("p.csv", "").error(), "p.csv: no header line");
}

TEST(PairStatsLog, TheTailReadsOnWholeLinesAndSkipsRowsThatDoNotRead) {
  poet::testing::ScratchDir dir;
  const std::filesystem::path path = dir.path() / "pair_stats.csv";
  const auto append = [&](const std::string& text) { std::ofstream(path, std::ios::binary | std::ios::app) << text; };
  PairStatsTail tail(path);
  EXPECT_TRUE(tail.rows_of(1).empty());  // no file yet
  append(std::string(kHeader) + "3,1,x,12.5,true,20,false,7\r\n3,2,x,bad,true,20,false,7\n4,1,x,13,fal");
  ASSERT_EQ(tail.rows_of(1).size(), 1u);
  EXPECT_TRUE(tail.rows_of(2).empty());
  append("se,21,true,8\n");
  ASSERT_EQ(tail.rows_of(1).size(), 2u);
  EXPECT_EQ(tail.rows_of(1)[1].best_score, 21);

  std::ofstream(path, std::ios::binary | std::ios::trunc) << kHeader << "5,1,x,1,true,2,false,9\n";  // cut back
  ASSERT_EQ(tail.rows_of(1).size(), 1u);
  EXPECT_EQ(tail.rows_of(1)[0].iteration, 5);
}

}  // namespace
}  // namespace poet
