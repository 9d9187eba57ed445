#pragma once
// Environment definitions between their in-memory form (envgen/env_encoding.h) and the schema's messages
// (pb::EnvEncoding, pb::EnvDef), for run configs and checkpoints. Conversion to proto is exact, so
// from_proto(to_proto(x)) gives x back bit for bit; reading a message is a boundary and validates.

#include "common/plumbing/expected.h"
#include "poet.pb.h"
#include "simulation/envgen/env_encoding.h"

namespace poet {

// An absent interval is an absent gene; an interval message must give both lo and hi. An empty or absent name
// becomes reference_name() of the genes. Errors name the field relative to the message ("pit_gap.hi: ...",
// "roughness: ..."), so a caller prefixes its own path.
Expected<EnvEncoding> encoding_from_proto(const pb::EnvEncoding& message);
pb::EnvEncoding to_proto(const EnvEncoding& encoding);

// As encoding_from_proto, plus the seed, which must be < kMaxEnvSeed; errors read "encoding.<field>: ..." or
// "seed: ...". An absent encoding is the flat one (every type absent, roughness 0).
Expected<EnvDef> env_def_from_proto(const pb::EnvDef& message);
pb::EnvDef to_proto(const EnvDef& def);

}  // namespace poet
