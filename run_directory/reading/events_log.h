#pragma once
// The one reader of events.jsonl (one JSON object per line, each with "iteration" and "event"), in the two ways
// it is read: the lines a checkpoint vouches for, strictly (the analysis tools' RunSnapshot), and a page of a live
// log's whole lines as they are (the status socket's /events).

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "common/plumbing/expected.h"

namespace poet {

// bytes: the log up to a checkpoint's size. Every line must be an event; a cut last line or a line that is not
// one is an error naming path and the line's number.
Expected<std::vector<nlohmann::json>> parse_events(const std::filesystem::path& path, std::string_view bytes);

struct EventLinesPage {
  std::vector<std::string> lines;  // as written, unchecked
  bool more = false;               // whole lines follow the page
};

// Lines [since, since + limit) of the log at path, whole lines only (a last line without its newline is still
// being written). No file yet: no lines. An error only when the file exists and cannot be read.
Expected<EventLinesPage> read_event_lines(const std::filesystem::path& path, int64_t since, int64_t limit);

}  // namespace poet
