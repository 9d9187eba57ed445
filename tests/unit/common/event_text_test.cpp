// Tests common/event_text: the one shape of an event line, from a view and from the engine's JSON events.

#include "event_text.h"

#include <gtest/gtest.h>

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

TEST(EventText, OddJsonEventsStillGiveALine) {
  EXPECT_EQ(describe_event(ordered_json{{"event", 5}}), "iteration null: event");
  EXPECT_EQ(describe_event(ordered_json::array({1, 2})), "[1,2]");
  EXPECT_FALSE(event_view(ordered_json("text")).has_value());
  EXPECT_EQ(describe_event(ordered_json{{"iteration", 1}, {"event", "x"}, {"name", "\xff"}}),
            "iteration 1: x name=\xff");  // a string is shown as it is
}

}  // namespace
}  // namespace poet
