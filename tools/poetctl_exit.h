#pragma once
// poetctl's exit code beside tool_flags.h's kExitUsage (2): 1 when the coordinator cannot be reached, answered
// with an error, or a file could not be made.

namespace poet {

inline constexpr int kExitUnreachable = 1;

}  // namespace poet
