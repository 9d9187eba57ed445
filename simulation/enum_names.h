#pragma once
// One way to name an enum's values: a table indexed by the value (the project's enums count from 0), with a
// fallback for a value outside it. The names are literals, so data() of a name is a C string.

#include <array>
#include <cstddef>
#include <string_view>

namespace poet {

template <class Enum, size_t N>
constexpr std::string_view enum_name(Enum value, const std::array<std::string_view, N>& names,
                                     std::string_view fallback) {
  const auto index = static_cast<size_t>(value);
  return index < N ? names[index] : fallback;
}

}  // namespace poet
