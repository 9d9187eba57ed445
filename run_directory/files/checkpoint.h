#pragma once
// A run's state (RunState) as the schema's Checkpoint message and back. to_checkpoint sets every field, so equal
// states serialise to equal bytes; doubles travel as IEEE bits, so from_checkpoint(to_checkpoint(s)) is s
// exactly. events_bytes and stats_bytes belong to the run directory and are left unset here; the arithmetic digest
// is this process's.

#include <cstdint>
#include <optional>
#include <string>

#include "common/plumbing/expected.h"
#include "engine/run_state.h"
#include "poet.pb.h"

namespace poet {

pb::Checkpoint to_checkpoint(const pb::RunConfig& config, const RunState& state);

// A checkpoint comes from disk, so it is checked as hostile input: the config validates, every environment is
// valid, θ, best θ and Adam's moments hold kParamCount finite values, pair ids are unique and increasing and
// below next_pair_id, every referenced pair exists, counters and iterations are in range, and the state is one
// the engine could have produced in its mode (check_state_consistency). The error names the field by its path
// ("pairs[3].theta: 12 values, expected 2804").
Expected<RunState> from_checkpoint(const pb::Checkpoint& checkpoint);

// Why this process must not resume a checkpoint written by a process with this arithmetic digest (nullopt: none
// written, a build before the project's own math): it would go on computing other numbers, as another run. nullopt
// when it computes as the writer did.
std::optional<std::string> arithmetic_refusal(std::optional<uint64_t> written_by);

// Why this build must not compute on from a checkpoint that holds fields it does not know (proto2 keeps them as
// unknown fields, new enum values included): a later build wrote them, and resumed here the run would drop them and
// go on as another run. The message names the fields by path ("pairs[0] field 22", at most five) and both versions:
// the checkpoint's written_by ("a later build" when it has none) and this build's. nullopt when every field is known.
std::optional<std::string> unknown_fields_refusal(const pb::Checkpoint& checkpoint);

// What a run is opened or restored for: to compute further, which a checkpoint of other arithmetic refuses, or
// only to read it and write the files derived from its checkpoint (poetctl unpack), which any checkpoint allows.
enum class OpenFor { kComputing, kReading };

}  // namespace poet
