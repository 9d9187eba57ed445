#pragma once
// A run directory as the Python module's Run reads it: read_run_snapshot (no lock taken, nothing written; a
// live run as of its last checkpoint) and poet-report's metrics as JSON, with the pairs' environments and θ.

#include <cstdint>
#include <string>
#include <vector>

namespace poet::python {

struct PairView {
  int id = 0;
  std::string env_json;  // the environment file's JSON (envs/*.env.json form)
  std::vector<double> theta;
  std::vector<double> best_theta;
};

struct RunView {
  std::string report_json;  // poet-report --json's document (default coverage sample, no target file)
  std::string events_json;  // a JSON array of the events the checkpoint has seen
  std::string stats_csv;    // pair_stats.csv as far as the checkpoint has seen it, its size and CRC-32 checked
  std::string config_text;
  int next_iteration = 0;
  bool live = false;
  std::vector<PairView> pairs;
};

// Throws std::invalid_argument with the report's message for a directory that is not a readable run.
RunView read_run_view(const std::string& dir);

}  // namespace poet::python
