// Tests common/text/event_text: the one shape of an event line, from a view and from the engine's JSON events.

#include "common/text/event_text.h"

#include <gtest/gtest.h>

#include "common/text/text_format.h"

namespace poet {
namespace {

using nlohmann::ordered_json;

TEST(EventText, ViewIsWrittenAsIterationNameAndFieldsInOrder) {
  EXPECT_EQ(describe_event(EventView{"12", "pair_created", {{"pair", "3"}, {"env", "r0.4"}}}),
            "iteration 12: pair_created pair=3 env=r0.4");
  EXPECT_EQ(describe_event(EventView{std::nullopt, std::nullopt, {{"unparsed", "x"}}}), "event unparsed=x");
}

TEST(EventText, JsonEventsKeepTheirFieldOrderAndWriteValuesAsJson) {
  ordered_json event = {{"iteration", 12}, {"event", "transfer"}, {"target", 2},  {"env", "r0.4"},
                        {"score", 0.5},    {"accepted", true},    {"ids", {1, 2}}};
  EXPECT_EQ(describe_event(event), "iteration 12: transfer target=2 env=r0.4 score=0.5 accepted=true ids=[1,2]");
}

// The log a person reads: a score to two decimals, a small value to four significant digits, whole numbers whole;
// events.jsonl keeps every digit.
TEST(EventText, NumbersAreWrittenWithTheDigitsThatMatter) {
  const ordered_json event = {{"iteration", 2},
                              {"event", "pair_created"},
                              {"seed", 866859},
                              {"score", -94.37845310320586},
                              {"novelty", 1.02469507659596},
                              {"distance_to_target", 0.02981423969999714},
                              {"best", 300.0},
                              {"threshold", 229.994}};
  EXPECT_EQ(describe_event(event),
            "iteration 2: pair_created seed=866859 score=-94.38 novelty=1.02 distance_to_target=0.02981 best=300 "
            "threshold=229.99");
  EXPECT_EQ(reading_text(0.009975029977012648), "0.009975");
  EXPECT_EQ(reading_text(-0.5), "-0.5");
  EXPECT_EQ(reading_text(1e20), "100000000000000000000.00");
}

TEST(EventText, OddJsonEventsStillGiveALine) {
  EXPECT_EQ(describe_event(ordered_json{{"event", 5}}), "iteration null: event");
  EXPECT_EQ(describe_event(ordered_json::array({1, 2})), "[1,2]");
  EXPECT_FALSE(event_view(ordered_json("text")).has_value());
  EXPECT_EQ(describe_event(ordered_json{{"iteration", 1}, {"event", "x"}, {"name", "\xff"}}),
            "iteration 1: x name=\xff");  // a string is shown as it is
}

}  // namespace
}  // namespace poet
