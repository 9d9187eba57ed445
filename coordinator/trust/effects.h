#pragma once
// What the referee (referee.h) asks of the dispatcher after an event: values, carried out by Dispatcher::apply in
// one place and in the order of the fields below — jobs put back, workers and keys refused, results taken, tasks
// reopened, jobs for the coordinator's own computation — and by the remote evaluator for what needs its sockets
// (the keys refused at the handshake, the coordinator's own runs).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coordinator/trust/standing.h"
#include "coordinator/trust/verification.h"
#include "simulation/rollout.h"

namespace poet {

// What an error Result from a holder means.
enum class ErrorVerdict {
  kFromUnproven,  // from a worker not proven: demoted, and the job goes to proven workers
  kRetry,         // from a proven worker: another proven worker says whether the error is real
  kStop,          // proven workers agree: the job fails, and the run stops
};

struct Effects {
  struct Refuse {
    WorkerId worker;
    std::string why;  // read after "this worker": "returned results that ..."
  };
  struct Take {
    uint64_t job = 0;
    WorkerId credited;      // whose answer the results are (kCoordinatorAnswer: the coordinator's own)
    bool final_now = true;  // else held back until the batch is whole
    std::vector<RolloutResult> results;
  };
  struct Reopen {
    size_t begin = 0;  // tasks [begin, end) of the batch, whose results were taken
    size_t end = 0;
    std::vector<Answer> held;  // the answers that differ: the new job holds them for a third witness
  };

  std::vector<uint64_t> requeue;  // jobs that wait for another answer: to the front of the queue unless held
  // Workers refused, in order: told why, removed, their results not yet final computed again. Before a job is taken,
  // so that their results held back do not become final with it.
  std::vector<Refuse> refuse;
  std::vector<std::string> refuse_keys;  // the CURVE keys of those found wrong: no handshake with them from now on
  std::optional<Take> take;              // a job's results are settled: the job ends
  std::optional<Reopen> reopen;          // results taken, found disputed: their tasks go out again
  std::vector<uint64_t> to_coordinator;  // jobs only the coordinator's own computation can settle
  std::optional<ErrorVerdict> error;     // an error Result's meaning
};

}  // namespace poet
