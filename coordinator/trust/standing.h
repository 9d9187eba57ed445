#pragma once
// A worker as trust sees it: who it is (a routing id), and its standing — proven or not, demoted, local, and what
// its answers showed. A record of the referee's (referee.h), which the dispatcher reads to schedule; only
// WorkerTrust (worker_trust.h) changes it.

#include <cstddef>
#include <cstdint>
#include <string>

namespace poet {

using Millis = int64_t;        // milliseconds on the dispatcher's monotonic clock
using WorkerId = std::string;  // the ROUTER's routing id of the worker's socket
using Witness = std::string;  // who vouches for a worker's answers: its CURVE key, else its routing id (verification.h)

// How far a worker is trusted (worker_trust.h says what each allows).
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

struct Standing {
  Witness witness;            // its CURVE key, or its routing id without CURVE: connections of one key are one witness
  bool local = false;         // started by this coordinator (showed local_token): proven from the start, never checked
  bool proven = false;        // local, or has returned a valid result: alive and answering (not: right)
  bool demoted = false;       // not proven, and let a lease expire or returned an error: given no more jobs
  int64_t checks_passed = 0;  // its answers that another worker or the coordinator computed alike
  int64_t answers_taken = 0;  // its answers whose results the batch kept (the others were another's, or redone)
  // of those, the ones taken with no other answer compared: every other answer of its was computed twice
  int64_t answers_taken_unchecked = 0;
  int64_t probation_answers = 0;  // the answers it gave before its probation ended (so far, while it lasts)
};

}  // namespace poet
