#include "common/text/event_text.h"

#include "common/text/text_format.h"

namespace poet {
namespace {

std::string json_text(const nlohmann::ordered_json& value) {
  return value.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace

std::string describe_event(const EventView& event) {
  std::string text = event.iteration ? "iteration " + *event.iteration + ": " : "";
  text += event.name ? *event.name : "event";
  for (const auto& [key, value] : event.fields) text += " " + key + "=" + value;
  return text;
}

std::optional<EventView> event_view(const nlohmann::ordered_json& event) {
  if (!event.is_object()) return std::nullopt;
  EventView view;
  view.iteration = event.value("iteration", nlohmann::ordered_json()).dump();
  const auto name = event.find("event");
  if (name != event.end() && name->is_string()) view.name = name->get<std::string>();
  for (const auto& [key, value] : event.items()) {
    if (key == "iteration" || key == "event") continue;
    view.fields.emplace_back(key, value.is_string()         ? value.get<std::string>()
                                  : value.is_number_float() ? reading_text(value.get<double>())
                                                            : json_text(value));
  }
  return view;
}

std::string describe_event(const nlohmann::ordered_json& event) {
  const std::optional<EventView> view = event_view(event);
  return view ? describe_event(*view) : json_text(event);
}

}  // namespace poet
