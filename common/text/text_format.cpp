#include "common/text/text_format.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace poet {

std::string number_text(double value) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, end);
}

std::string number_text(int64_t value) { return std::to_string(value); }

std::string reading_text(double value) {
  if (!std::isfinite(value)) return number_text(value);
  if (value == std::floor(value) && std::abs(value) < 1e15) return std::to_string(static_cast<long long>(value));
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, std::abs(value) >= 1 ? "%.2f" : "%.4g", value);
  return buffer;
}

std::string hex_text(uint64_t value, int digits) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out(static_cast<size_t>(std::clamp(digits, 1, 16)), '0');
  for (auto it = out.rbegin(); it != out.rend(); ++it, value >>= 4) *it = kHex[value & 15];
  return out;
}

std::string peer_id_text(std::string_view id) {
  const bool printable = !id.empty() && std::all_of(id.begin(), id.end(), [](char c) { return c > 0x20 && c < 0x7F; });
  if (printable) return std::string(id);
  std::string out = "0x";
  for (char c : id) out += hex_text(static_cast<unsigned char>(c), 2);
  return out;
}

std::string vprintf_text(const char* format, va_list args) {
  va_list measure;
  va_copy(measure, args);
  const int size = std::vsnprintf(nullptr, 0, format, measure);
  va_end(measure);
  std::string text(static_cast<size_t>(std::max(size, 0)), '\0');
  if (size > 0) std::vsnprintf(text.data(), text.size() + 1, format, args);  // its '\0' on the string's own
  return text;
}

void append_printf(std::string& out, const char* format, ...) {
  va_list args;
  va_start(args, format);
  out += vprintf_text(format, args);
  va_end(args);
}

}  // namespace poet
