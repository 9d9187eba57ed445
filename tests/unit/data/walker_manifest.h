#pragma once
// The manifests of data/walkers/ (shipped.json, generalists.json) for the tests that check their walkers: the
// entries, each with its walker's policy file loaded.

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/formats/policy/policy_file.h"

namespace poet::test {

inline const std::string kSourceRoot = POET_SOURCE_DIR;

struct ManifestWalker {
  std::string name;
  nlohmann::json entry;
  Expected<PolicyFile> walker;  // the entry's "walker", loaded from the source tree
};

// data/walkers/FILE's entries; empty when the file is missing or holds none (a test asserts it is not).
inline std::vector<ManifestWalker> read_walker_manifest(const std::string& file) {
  std::ifstream in(kSourceRoot + "/data/walkers/" + file);
  if (!in) return {};
  std::vector<ManifestWalker> walkers;
  for (const nlohmann::json& entry : nlohmann::json::parse(in)) {
    walkers.push_back(
        {entry.at("name"), entry, load_policy(kSourceRoot + "/" + entry.at("walker").get<std::string>())});
  }
  return walkers;
}

}  // namespace poet::test
