#pragma once
// Access to the optional external reference data (trained walkers and step traces of the authors' walker) for the
// alignment tests. The directory is POET_REFERENCE_DIR; when it is absent the tests skip and say why.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "common/formats/policy/policy_file.h"

namespace poet::alignment {

inline std::filesystem::path reference_dir() { return POET_REFERENCE_DIR; }

// Why the reference data cannot be read (POET_REFERENCE_DIR not set, or no walker-traces/ in it), or empty.
inline std::string reference_missing() {
  if (reference_dir().empty())
    return "POET_REFERENCE_DIR is not set (configure with -DPOET_REFERENCE_DIR=DIR, or run POET_REFERENCE_DIR=DIR "
           "bash deploy/test.sh)";
  if (!std::filesystem::exists(reference_dir() / "walker-traces"))
    return "reference data not found at " + reference_dir().string();
  return "";
}

// Skips the calling test (with the reason) when the reference data is not there.
#define POET_REQUIRE_REFERENCE()                                                                                \
  do {                                                                                                          \
    if (const std::string missing = ::poet::alignment::reference_missing(); !missing.empty())                   \
      GTEST_SKIP() << missing                                                                                   \
                   << ": these alignment checks need the authors' traces and the estool walkers; the walker's " \
                      "own unit tests still run";                                                               \
  } while (0)

inline nlohmann::json load_trace(const std::string& name) {
  std::ifstream in(reference_dir() / "walker-traces" / name);
  return nlohmann::json::parse(in);
}

inline std::vector<double> load_zoo_policy(const std::string& relative) {
  auto p = load_policy(reference_dir() / "estool-zoo" / relative);
  if (!p) throw std::runtime_error(p.error());
  return p->params;
}

}  // namespace poet::alignment
