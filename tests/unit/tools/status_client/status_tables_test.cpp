// Tests tools/status_client/status_tables.cpp's event_view: an /events entry becomes the same line shape as
// the coordinator's log (common/text/event_text), its fields sorted by name and whole numbers written out in full.

#include "tools/status_client/status_tables.h"

#include <google/protobuf/util/json_util.h>
#include <gtest/gtest.h>

namespace poet {
namespace {

google::protobuf::Struct event(const std::string& json) {
  google::protobuf::Struct out;
  EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(json, &out).ok()) << json;
  return out;
}

TEST(StatusTables, EventsAreDescribedWithSortedFields) {
  EXPECT_EQ(describe_event(event_view(event(
                R"({"iteration": 12, "event": "transfer", "target": 2, "score": 0.25, "env": "r0.4", "ok": true})"))),
            "iteration 12: transfer env=r0.4 ok=true score=0.25 target=2");
  EXPECT_EQ(describe_event(event_view(event(R"({"steps": 1000000, "ids": [1, 2], "none": null})"))),
            "event ids=[1,2] none=null steps=1000000");
  EXPECT_EQ(describe_event(event_view(event(R"({"unparsed": "not json"})"))), "event unparsed=not json");
  // numbers with the digits a reader needs, as in the coordinator's log
  EXPECT_EQ(describe_event(event_view(event(R"({"score": -94.37845310320586, "novelty": 0.09627736795473842})"))),
            "event novelty=0.09628 score=-94.38");
}

}  // namespace
}  // namespace poet
