#pragma once
// The engine's events as the run's log writes them: one JSON object per event, {"iteration": t, "event": name,
// fields...} in a fixed field order, so equal runs write equal bytes (events.jsonl; spec §3's record).

#include <nlohmann/json.hpp>
#include <string_view>
#include <vector>

#include "engine/iteration_report.h"
#include "engine/run_event.h"

namespace poet {

nlohmann::ordered_json event_json(int iteration, const RunEvent& event);

// A "solved" event's "by": "admission", "es" or "transfer".
std::string_view solved_by_name(SolvedBy by);

// Every event of the report, in order.
std::vector<nlohmann::ordered_json> events_json(const IterationReport& report);

}  // namespace poet
