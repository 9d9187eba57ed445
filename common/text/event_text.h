#pragma once
// One event of a run as a line for people: "iteration 12: pair_created pair=3 env=r0.4". The coordinator logs
// its events from JSON and poetctl prints them from the status socket's protobuf Struct; each turns its own
// representation into an EventView (its values already written as text), and describe_event writes the line.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace poet {

struct EventView {
  std::optional<std::string> iteration;                     // absent: the line has no "iteration N: " prefix
  std::optional<std::string> name;                          // the "event" field; absent: "event"
  std::vector<std::pair<std::string, std::string>> fields;  // the others, in the order to show them
};

// "iteration 12: pair_created pair=3 env=r0.4".
std::string describe_event(const EventView& event);

// An event of the run log as the engine wrote it: fields in their order, strings as they are, other values as
// JSON (invalid UTF-8 replaced); "iteration null" when it has none. Not an object: nullopt.
std::optional<EventView> event_view(const nlohmann::ordered_json& event);

// The line for a JSON event: describe_event(event_view(event)), or the JSON itself when it is not an object.
std::string describe_event(const nlohmann::ordered_json& event);

}  // namespace poet
