#pragma once
// Environments drawn at a difficulty level as the paper draws its coverage sample (spec §3): uniform in the box
// e ∈ [0,8]×[0,8]×[0,8]×[0,3]×[0,3], drawn again until lo ≤ hi for the gap and the stump height and the vector is
// at the level asked for; and the obstacle course that a 5-vector stands for.

#include <string>

#include "simulation/envgen/env_distance.h"
#include "simulation/rng.h"

namespace poet {

// One vector at `level` (any of the four), drawn from `stream`; the draws it consumes depend only on the stream.
EnvVector draw_env_vector(RandomStream& stream, Difficulty level);

// The course whose 5-vector is e: roughness e[0], pits of gaps [e[1], e[2]] when e[2] > 0, stumps of heights
// [e[3], e[4]] when e[4] > 0 with the width and float mutation gives a new stump type ([1, 2) and [0, 1)); no
// stairs, which the 5-vector does not describe.
EnvEncoding course_of(const EnvVector& e, std::string name);

}  // namespace poet
