#include "common/plumbing/local_token.h"

#include <random>

namespace poet {

std::string make_local_token() {
  static const char* kHex = "0123456789abcdef";
  std::random_device device;  // the operating system's entropy (/dev/urandom on Linux)
  std::string token;
  for (int i = 0; i < 4; ++i) {
    const uint32_t word = device();
    for (int nibble = 0; nibble < 8; ++nibble) token += kHex[(word >> (4 * nibble)) & 15];
  }
  return token;
}

uint64_t make_verify_secret() {
  std::random_device device;
  return (static_cast<uint64_t>(device()) << 32) | device();
}

}  // namespace poet
