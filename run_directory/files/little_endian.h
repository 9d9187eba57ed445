#pragma once
// Fixed-width little-endian integers in the byte strings of the run's own file formats (the checkpoint's header,
// run packs), so that a file reads the same on any machine.

#include <cstdint>
#include <string>
#include <string_view>

namespace poet {

// Appends the low `bytes` bytes of value, least significant first.
inline void put_le(std::string& out, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xff));
}

// The `bytes`-byte value at offset; the caller has checked that in holds offset + bytes bytes.
inline uint64_t get_le(std::string_view in, size_t offset, int bytes) {
  uint64_t value = 0;
  for (int i = bytes - 1; i >= 0; --i) value = (value << 8) | static_cast<unsigned char>(in[offset + i]);
  return value;
}

}  // namespace poet
