#pragma once
// A CPPN genome in environment files, under the encoding's "cppn" key:
//   {"nodes": [{"id": 0, "role": "input"}, {"id": 1, "role": "output", "activation": "identity", "bias": b},
//              {"id": 2, "role": "hidden", "activation": "sin", "bias": b}, ...],
//    "connections": [{"from": 0, "to": 2, "weight": w}, ...], "scale": s}
// Reading is a boundary: unknown or missing keys, wrong types, unknown activations and roles, and anything
// validate(CppnGenome) refuses give an error naming the field ("cppn.nodes[2].activation: ..."). Nodes and
// connections are listed in the canonical order (nodes by id, connections by (from, to)), as they are written, so
// an error's index is the file's. Numbers are written so they parse back bit for bit.

#include <nlohmann/json.hpp>

#include "common/plumbing/expected.h"
#include "simulation/envgen/cppn_genome.h"

namespace poet {

nlohmann::json cppn_to_json(const CppnGenome& genome);
Expected<CppnGenome> cppn_from_json(const nlohmann::json& object);

}  // namespace poet
