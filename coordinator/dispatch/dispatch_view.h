#pragma once
// What the dispatcher shows of itself at one moment (Dispatcher::view): its workers and its counters, taken on its
// socket thread and handed to the status board as they are. No protobuf or sockets: the status socket's renderers
// read it.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace poet {

using Millis = int64_t;        // milliseconds on the dispatcher's monotonic clock
using WorkerId = std::string;  // the ROUTER's routing id of the worker's socket

// How far the dispatcher trusts a worker (dispatcher.h says what each allows).
enum class Trust {
  kTrial,      // has answered no job yet: holds one at a time
  kProbation,  // answers, and every answer is checked until probation_checks of them were found right
  kProven,     // past its probation (or local, or with verification off): a fraction of its answers is checked
  kDemoted,    // answered nothing, and let a lease run out or returned an error: given no more jobs
  kRefused,    // returned wrong results: refused from then on, on any connection with its key
};
constexpr const char* name(Trust trust) {
  constexpr const char* kNames[] = {"trial", "probation", "proven", "demoted", "refused"};
  return kNames[static_cast<size_t>(trust)];
}

struct WorkerView {
  WorkerId id;       // any bytes: shown as is when printable ASCII, else as hex
  std::string name;  // the name it gave (host and pid)
  int threads = 0;
  uint64_t fingerprint_digest = 0;
  int64_t jobs_done = 0;
  int64_t results_done = 0;
  Millis last_heard = 0;
  size_t jobs_held = 0;
  int64_t checks_passed = 0;  // its answers that another worker or the coordinator computed alike
  int64_t answers_taken = 0;  // its answers whose results the batch kept (the others were another's, or redone)
  // of those, the ones taken with no other answer compared: every other answer of its was computed twice
  int64_t answers_taken_unchecked = 0;
  int64_t probation_answers = 0;  // the answers it gave before its probation ended (so far, while it lasts)
  Trust trust = Trust::kTrial;  // filled by Dispatcher::view and workers()
  bool local = false;           // started by this coordinator (showed local_token)
  bool proven = false;          // local, or has returned a valid result: alive and answering (not: right)
  bool demoted = false;         // not proven, and let a lease expire or returned an error: given no more jobs
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
