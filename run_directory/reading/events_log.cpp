#include "run_directory/reading/events_log.h"

#include <fstream>

#include "common/plumbing/text_file.h"
#include "run_directory/reading/log_lines.h"

namespace poet {

Expected<std::vector<nlohmann::json>> parse_events(const std::filesystem::path& path, std::string_view bytes) {
  const LogLines log = whole_lines(bytes);
  if (log.consumed != bytes.size())
    return Unexpected{path.string() + ": the last line recorded by the checkpoint is cut"};
  std::vector<nlohmann::json> events;
  for (size_t i = 0; i < log.lines.size(); ++i) {
    nlohmann::json event = nlohmann::json::parse(log.lines[i], nullptr, false);
    if (event.is_discarded() || !event.is_object() || !event.contains("iteration") || !event.contains("event") ||
        !event["iteration"].is_number_integer() || !event["event"].is_string())
      return Unexpected{path.string() + ":" + std::to_string(i + 1) +
                        ": not an event (a JSON object with \"iteration\" and \"event\")"};
    events.push_back(std::move(event));
  }
  return events;
}

Expected<EventLinesPage> read_event_lines(const std::filesystem::path& path, int64_t since, int64_t limit) {
  EventLinesPage page;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const Expected<bool> exists = path_exists(path);
    if (!exists) return Unexpected{path.string() + ": " + exists.error()};
    if (!*exists) return page;  // no events yet
    return Unexpected{path.string() + ": cannot read"};
  }
  std::string line;
  int64_t index = 0;
  while (std::getline(in, line)) {
    if (in.eof()) break;  // a last line without its newline is still being written
    if (index++ < since) continue;
    if (static_cast<int64_t>(page.lines.size()) == limit) {
      page.more = true;
      break;
    }
    page.lines.push_back(std::move(line));
  }
  if (in.bad()) return Unexpected{path.string() + ": read error"};
  return page;
}

}  // namespace poet
