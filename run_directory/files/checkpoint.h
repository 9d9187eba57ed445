#pragma once
// A run's state (RunState) as the schema's Checkpoint message and back. to_checkpoint sets every field, so equal
// states serialise to equal bytes; doubles travel as IEEE bits, so from_checkpoint(to_checkpoint(s)) is s
// exactly. events_bytes and stats_bytes belong to the run directory and are left unset here.

#include "engine/run_state.h"
#include "plumbing/expected.h"
#include "poet.pb.h"

namespace poet {

pb::Checkpoint to_checkpoint(const pb::RunConfig& config, const RunState& state);

// A checkpoint comes from disk, so it is checked as hostile input: the config validates, every environment is
// valid, θ, best θ and Adam's moments hold kParamCount finite values, pair ids are unique and increasing and
// below next_pair_id, every referenced pair exists, counters and iterations are in range, and the state is one
// the engine could have produced in its mode (check_state_consistency). The error names the field by its path
// ("pairs[3].theta: 12 values, expected 2804").
Expected<RunState> from_checkpoint(const pb::Checkpoint& checkpoint);

}  // namespace poet
