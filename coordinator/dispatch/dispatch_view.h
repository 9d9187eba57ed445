#pragma once
// What the dispatcher shows of itself at one moment (Dispatcher::view): its workers and its counters, taken on its
// socket thread and handed to the status board as they are. No protobuf or sockets: the status socket's renderers
// read it.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "coordinator/trust/standing.h"

namespace poet {

// What the dispatcher knows of a connected worker: what its Hello said, and what it did since.
struct WorkerFacts {
  WorkerId id;       // any bytes: shown as is when printable ASCII, else as hex
  std::string name;  // the name it gave (host and pid)
  int threads = 0;
  uint64_t fingerprint_digest = 0;
  uint64_t arithmetic_digest = 0;  // what its machine computes, as its Hello said (equal to the coordinator's)
  int64_t jobs_done = 0;
  int64_t results_done = 0;
  Millis last_heard = 0;
};

// A connected worker as the status socket shows it: its standing (the referee's) and what the dispatcher knows of it.
struct WorkerView : Standing, WorkerFacts {
  size_t jobs_held = 0;
  Trust trust = Trust::kTrial;
};

inline constexpr size_t kMaxRefusedShown = 64;

struct DispatchView {
  std::vector<WorkerView> workers;  // in the order they said Hello
  std::vector<WorkerView> refused;  // the workers refused for wrong results, the latest kMaxRefusedShown, in order
  Millis at = 0;                    // when it was taken: a worker was last heard from at - last_heard ms before
  size_t ready_workers = 0;         // those that may be sent jobs
  int64_t queue_depth = 0;
  int64_t in_flight_jobs = 0;
  std::map<std::string, int64_t> dropped_frames;  // by reason (drop_reason.h)
  int64_t workers_joined = 0;                     // Welcomes given since the coordinator started
  int64_t workers_lost = 0;                       // workers removed for silence or a failed send
  int64_t backup_jobs = 0;                        // jobs also sent to a second worker (dispatcher.h)
  int64_t leases_expired = 0;                     // jobs taken back from workers not yet proven
  int64_t workers_demoted = 0;                    // workers not proven given no more jobs
  int64_t verified_jobs = 0;                      // answers found right by a second worker or the coordinator
  int64_t wrong_workers = 0;                      // workers refused for wrong results
  int64_t coordinator_checks = 0;                 // jobs the coordinator ran itself, no worker able to check them
  int64_t rollbacks = 0;                          // times the run went back to a checkpoint before a liar's answers
};

}  // namespace poet
