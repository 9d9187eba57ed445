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

}  // namespace poet
