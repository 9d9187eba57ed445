#pragma once
// Access to the optional external reference data (trained walkers and step traces of the authors' walker) for the
// alignment tests. The directory is POET_REFERENCE_DIR; when it is absent the tests skip and say why.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "policy/policy_file.h"

namespace poet::alignment {

inline std::filesystem::path reference_dir() { return POET_REFERENCE_DIR; }

// Skips the calling test (with the reason) when the reference data is not there.
#define POET_REQUIRE_REFERENCE()                                                                              \
  do {                                                                                                        \
    if (!std::filesystem::exists(::poet::alignment::reference_dir() / "walker-traces"))                       \
      GTEST_SKIP() << "reference data not found at " << ::poet::alignment::reference_dir()                    \
                   << " (set -DPOET_REFERENCE_DIR=...): these alignment checks need the authors' traces and " \
                      "the estool walkers; the walker's own unit tests still run";                            \
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
