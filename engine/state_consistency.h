#pragma once
// Whether a state is one the engine could have produced from its config: the rules the loop keeps (one pair and
// a curriculum in DIRECT_PATH, one pair on the target in ES_ALONE, at least one and at most active_cap active
// pairs in the POET modes, lineage in creation order, counters that agree with the archive, optimizer values
// within their decays' ranges). The engine relies on these rules, so a checkpoint that breaks one is refused
// rather than run (a DIRECT_PATH state without stages would crash the curriculum's first step).

#include <optional>
#include <string>

#include "engine/run_state.h"

namespace poet {

// Nothing when state keeps every rule, else the first broken one as "field: what is wrong" with the values.
// Precondition: the fields are individually valid (from_checkpoint's checks passed).
std::optional<std::string> check_state_consistency(const RunState& state);

}  // namespace poet
