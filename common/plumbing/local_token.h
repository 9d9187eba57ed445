#pragma once
// The secret by which a worker shows the coordinator that started it (--local-workers) that it is its own: given
// in the worker's environment (not its command line, which any local user can read) and told in its Hello. A
// local worker is trusted from the start; others earn trust (the coordinator's trust/).

#include <cstdint>
#include <string>

namespace poet {

inline constexpr char kLocalTokenVariable[] = "POET_LOCAL_TOKEN";

// 128 random bits from the operating system, as 32 hex digits.
std::string make_local_token();

// 64 random bits from the operating system: the secret from which the coordinator draws which answers it checks
// (its verify_secret), fresh in each coordinator process and never sent or written.
uint64_t make_verify_secret();

}  // namespace poet
