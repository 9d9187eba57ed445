#pragma once
// The direct-path curriculum control (spec §3 "Controls"): environments from flat toward a target, one mutation
// step at a time.

#include "simulation/envgen/env_encoding.h"
#include "simulation/rng.h"

namespace poet {

// The next stage's encoding: each parameter of the target's present types independently stays or increases by
// its mutation step with probability 1/2 (one uniform01() < 0.5 draw each, in the order roughness, pit gap lo/hi,
// stump height lo/hi, stair height lo/hi), clamped at the target's value. An absent type of
// the target stays absent; an absent type of the current encoding appears (one draw) at its initial interval
// clamped to the target, with the target's fixed genes (and, for stairs, its step count). Draws repeat until something
// changes; the current encoding must not equal the target's genes. Both encodings must be valid; so is the result.
EnvEncoding step_toward(const EnvEncoding& current, const EnvEncoding& target, RandomStream& stream);

}  // namespace poet
