#pragma once
// What poet-coordinator was asked on its command line (coordinator/main.cpp parses it): the run, where its rollouts
// run, and the sockets it serves.

#include <algorithm>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/protocol/status_defaults.h"
#include "common/protocol/wire_timing.h"

namespace poet {

struct DaemonOptions {
  std::string config_path;
  std::string run_dir;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::optional<int> iterations;
  bool resume = false;
  std::string from_pack;  // a run pack restored into the (new or empty) run directory before the resume
  bool quiet = false;
  std::string log_level = "info";
  std::string listen;     // workers connect here; empty: rollouts on threads of this process
  std::string advertise_host;  // the host name in the endpoint file for a wildcard --listen; empty: gethostname
  int local_workers = 0;  // worker processes to start and supervise on this machine
  int liveness_ms = wire_timing::kLivenessMs;
  std::string worker_binary;
  std::string status_address = kCoordinatorStatusAddress;  // the HTTP status socket; empty: none
  std::string health_address;                              // the probes' listener (/healthz alone); empty: none
  std::string curve_keys;                                  // CURVE key directory; empty: no authentication
  std::string start_from;                 // a policy file for the first pair's θ; empty: the init stream
  std::optional<double> verify_fraction;  // default: kListenVerifyFraction with --listen and no CURVE
  // A run found finished when opened stays up this long, telling each worker that connects that the run is finished
  // (seconds; 0: exit at once). Workers started beside it by an orchestrator would otherwise wait for it for ever.
  int linger_seconds = 0;
};

}  // namespace poet
