#pragma once
// Reading a field of an event from events.jsonl: the log is read, not trusted, so a missing, null or mistyped
// field gives the caller's fallback instead of an exception.

#include <nlohmann/json.hpp>

namespace poet {

template <class T>
T field_or(const nlohmann::json& event, const char* name, T fallback) {
  const auto found = event.find(name);
  if (found == event.end() || found->is_null()) return fallback;
  try {
    return found->get<T>();
  } catch (const nlohmann::json::exception&) {
    return fallback;
  }
}

}  // namespace poet
