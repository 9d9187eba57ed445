#pragma once
// Whether bytes are well-formed UTF-8 (no overlong forms, surrogates or code points past U+10FFFF), and text made
// so. Names read from files and the wire must be, because JSON and protobuf's text and JSON printers refuse
// anything else. Hand-written: none of the libraries in use offers it publicly (protobuf's is internal).

#include <string>
#include <string_view>

namespace poet {

bool is_valid_utf8(std::string_view text);

// The text with every byte that is not part of well-formed UTF-8 replaced by '?' (names from config files and
// paths from clients, before they go into JSON).
std::string valid_utf8(std::string_view text);

// The text made safe to print on a terminal: valid_utf8, then every control character but newline and tab — C0,
// DEL and C1 (U+0080..U+009F) — written as \u00XX, so that text from a peer (a server's answer) cannot move the
// cursor, retitle the window or hide what came before. Within a JSON string \u00XX means the same character, so
// the strings of a JSON answer keep their values (a CR between tokens, which JSON allows, does not stay valid).
std::string printable_text(std::string_view text);

}  // namespace poet
