#include "common/text/utf8.h"

#include <utility>

#include "common/text/text_format.h"

namespace poet {
namespace {

// The length of the well-formed sequence starting at text[i], or 0 when the bytes there are not one.
size_t sequence_length(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  if (lead < 0x80) return 1;
  size_t length = 0;
  unsigned char low = 0x80;  // the second byte's range, narrowed against overlong forms and surrogates
  unsigned char high = 0xBF;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (i + length > text.size()) return 0;
  if (byte(i + 1) < low || byte(i + 1) > high) return 0;
  for (size_t k = 2; k < length; ++k)
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  return length;
}

// The control character that starts at text[i] (its code point, and how many bytes it takes), or 0 bytes for
// any other character. C1 controls are two bytes in UTF-8 (C2 80 to C2 9F).
std::pair<unsigned, size_t> control_at(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  if ((byte(i) < 0x20 && byte(i) != '\n' && byte(i) != '\t') || byte(i) == 0x7F) return {byte(i), 1};
  if (byte(i) == 0xC2 && i + 1 < text.size() && byte(i + 1) >= 0x80 && byte(i + 1) <= 0x9F) return {byte(i + 1), 2};
  return {0, 0};
}

}  // namespace

bool is_valid_utf8(std::string_view text) {
  for (size_t i = 0, length; i < text.size(); i += length)
    if ((length = sequence_length(text, i)) == 0) return false;
  return true;
}

std::string valid_utf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const size_t length = sequence_length(text, i);
    if (length == 0) {
      out += '?';
      ++i;
    } else {
      out.append(text.substr(i, length));
      i += length;
    }
  }
  return out;
}

std::string printable_text(std::string_view text) {
  const std::string valid = valid_utf8(text);
  std::string out;
  out.reserve(valid.size());
  for (size_t i = 0; i < valid.size();) {
    const auto [code, length] = control_at(valid, i);
    if (length == 0) {
      out += valid[i++];
      continue;
    }
    out += "\\u" + hex_text(code, 4);
    i += length;
  }
  return out;
}

}  // namespace poet
