#pragma once
// The fields of one CSV line as the run files write them: comma-separated, a field in double quotes may hold
// commas and doubled quotes. No newlines inside fields (the writers quote them, and the readers read by line).

#include <charconv>
#include <string>
#include <string_view>
#include <vector>

namespace poet {

std::vector<std::string> csv_fields(std::string_view line);

// A whole field as a number (integer or double, std::from_chars' forms); false when any of it is not.
template <class T>
bool parse_field(std::string_view text, T& value) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  return ec == std::errc() && ptr == end;
}

}  // namespace poet
