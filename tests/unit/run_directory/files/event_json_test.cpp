// Tests run_directory/files/event_json.cpp: each event the engine reports becomes the events.jsonl object the run's
// log has always held — the same names, fields, field order and number forms, byte for byte.

#include "run_directory/files/event_json.h"

#include <gtest/gtest.h>

namespace poet {
namespace {

std::string line(int iteration, const RunEvent& event) { return event_json(iteration, event).dump(); }

TEST(EventJson, EveryKindWritesItsFieldsInTheLogsOrder) {
  EXPECT_EQ(line(3, SolvedEvent{2, "r1.5", 231.25, 40, SolvedBy::kTransfer}),
            R"({"iteration":3,"event":"solved","pair":2,"env":"r1.5","score":231.25,"iterations_to_solve":40,)"
            R"("by":"transfer"})");

  ChildEvent duplicate{4, 1, "dup", {1, 0.5, 0, 2, 0}, true, std::nullopt, false};
  EXPECT_EQ(line(6, duplicate),
            R"({"iteration":6,"event":"child","attempt":4,"parent":1,"env":"dup","e":[1.0,0.5,0.0,2.0,0.0],)"
            R"("duplicate":true})");
  ChildEvent evaluated{0, 1, "kid", {0, 0, 0, 0, 0.25}, false, -12.5, false};
  EXPECT_EQ(line(6, evaluated),
            R"({"iteration":6,"event":"child","attempt":0,"parent":1,"env":"kid","e":[0.0,0.0,0.0,0.0,0.25],)"
            R"("duplicate":false,"mc_score":-12.5,"passed_mc":false})");

  EXPECT_EQ(line(8, PairCreatedEvent{5, "kid", 999999u, 1, -1, true, 30.5, 0.125}),
            R"({"iteration":8,"event":"pair_created","pair":5,"env":"kid","seed":999999,"parent":1,"source":-1,)"
            R"("proposal":true,"score":30.5,"novelty":0.125})");

  EXPECT_EQ(line(8, ReproductionEvent{}), R"({"iteration":8,"event":"reproduction","eligible":0})");
  EXPECT_EQ(line(8, ReproductionEvent{2, 8, 1, 3, 1, std::nullopt}),
            R"({"iteration":8,"event":"reproduction","eligible":2,"tried":8,"duplicates":1,"passed_mc":3,)"
            R"("admitted":1})");
  // with PATA-EC novelty, what the characterisations cost: (3 archived + 3 passing) environments × 3 agents
  EXPECT_EQ(line(8, ReproductionEvent{2, 8, 1, 3, 1, 18}),
            R"({"iteration":8,"event":"reproduction","eligible":2,"tried":8,"duplicates":1,"passed_mc":3,)"
            R"("admitted":1,"pata_ec_evaluations":18})");

  EXPECT_EQ(line(8, PairRetiredEvent{0, "flat", true}),
            R"({"iteration":8,"event":"pair_retired","pair":0,"env":"flat","solved":true})");

  EXPECT_EQ(line(25, TransferEvent{3, 1, false, 250, 100.5}),
            R"({"iteration":25,"event":"transfer","target":3,"source":1,"proposal":false,"score":250.0,)"
            R"("previous_score":100.5})");
  EXPECT_EQ(line(25, TransferRoundEvent{true, 3, 6, 6, 1, 204, std::nullopt}),
            R"({"iteration":25,"event":"transfer_round","test":"full","pairs":3,"candidates":6,"proposals":6,)"
            R"("accepted":1,"rollouts":204})");
  EXPECT_EQ(line(25, TransferRoundEvent{false, 3, 6, 2, 0, 72, std::nullopt}),
            R"({"iteration":25,"event":"transfer_round","test":"threshold","pairs":3,"candidates":6,)"
            R"("proposals":2,"accepted":0,"rollouts":72})");

  EXPECT_EQ(line(9, StageEvent{true, 1, "r1", 0.5}),
            R"({"iteration":9,"event":"stage_solved","stage":1,"env":"r1","distance_to_target":0.5})");
  EXPECT_EQ(line(9, StageEvent{false, 2, "r2", 0.25}),
            R"({"iteration":9,"event":"stage_advanced","stage":2,"env":"r2","distance_to_target":0.25})");
  EXPECT_EQ(line(9, RunFinishedEvent{true, 12}),
            R"({"iteration":9,"event":"run_finished","reason":"target solved","es_steps":12})");
  EXPECT_EQ(line(9, RunFinishedEvent{false, 20}),
            R"({"iteration":9,"event":"run_finished","reason":"budget spent","es_steps":20})");
}

TEST(EventJson, AReportsEventsKeepTheirOrderAndIteration) {
  IterationReport report;
  report.iteration = 4;
  report.events = {ReproductionEvent{}, PairRetiredEvent{1, "a", false}};
  const std::vector<nlohmann::ordered_json> events = events_json(report);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0]["event"], "reproduction");
  EXPECT_EQ(events[1]["event"], "pair_retired");
  EXPECT_EQ(events[1]["iteration"], 4);
}

}  // namespace
}  // namespace poet
