#pragma once
// This machine's name, for what a process tells others about itself: a worker's default name, the host in the
// coordinator's endpoint file, who left a stop request.

#include <string>

namespace poet {

// gethostname(), or "localhost" when the machine has none.
std::string host_name();

}  // namespace poet
