// Tests run_directory/reading/events_log.cpp: the strict reading of the events a checkpoint vouches for, and the
// pages of a live log's whole lines.

#include "run_directory/reading/events_log.h"

#include <gtest/gtest.h>

#include <fstream>

#include "scratch_dir.h"

namespace poet {
namespace {

TEST(EventsLog, StrictReadingGivesEveryEventOrNamesTheBadLine) {
  Expected<std::vector<nlohmann::json>> read =
      parse_events("e.jsonl", "{\"iteration\":1,\"event\":\"a\"}\n{\"iteration\":2,\"event\":\"b\",\"pair\":3}\n");
  ASSERT_TRUE(read) << read.error();
  ASSERT_EQ(read->size(), 2u);
  EXPECT_EQ((*read)[1]["pair"], 3);
  EXPECT_EQ(parse_events("e.jsonl", "{\"iteration\":1,\"event\":\"a\"}\n{\"event\":\"b\"}\n").error(),
            "e.jsonl:2: not an event (a JSON object with \"iteration\" and \"event\")");
  EXPECT_EQ(parse_events("e.jsonl", "{\"iteration\":1,\"event\":\"a\"}").error(),
            "e.jsonl: the last line recorded by the checkpoint is cut");
}

TEST(EventsLog, PagesHoldWholeLinesAndSayWhetherMoreFollow) {
  poet::testing::ScratchDir dir;
  const std::filesystem::path path = dir.path() / "events.jsonl";
  Expected<EventLinesPage> none = read_event_lines(path, 0, 10);
  ASSERT_TRUE(none);
  EXPECT_TRUE(none->lines.empty());
  std::ofstream(path, std::ios::binary) << "a\nb\nc\nd";  // "d" is still being written
  Expected<EventLinesPage> page = read_event_lines(path, 1, 1);
  ASSERT_TRUE(page);
  EXPECT_EQ(page->lines, std::vector<std::string>{"b"});
  EXPECT_TRUE(page->more);
  Expected<EventLinesPage> rest = read_event_lines(path, 1, 10);
  EXPECT_EQ(rest->lines, (std::vector<std::string>{"b", "c"}));
  EXPECT_FALSE(rest->more);
  EXPECT_TRUE(read_event_lines(path, 5, 10)->lines.empty());
}

}  // namespace
}  // namespace poet
