#pragma once
// A job as trust sees it: whether it was chosen for a check, who failed it, and the answers it holds until another
// agrees or decides. A record of the referee's (referee.h), which the dispatcher reads to schedule; only WorkerTrust
// (worker_trust.h) changes it.

#include <algorithm>
#include <set>
#include <vector>

#include "coordinator/trust/standing.h"
#include "coordinator/trust/verification.h"

namespace poet {

struct JobTrust {
  bool chosen = false;          // chosen for a check: an answer from a worker that is not local needs a second
  bool tainted = false;         // a worker not proven failed it: proven workers take it while any is connected
  std::set<WorkerId> failed;    // workers that returned an error or let their lease expire: not sent to them again
  std::set<Witness> refusing;   // the witnesses of proven workers that returned an error for it (a key counts once)
  std::vector<Answer> answers;  // answers awaiting a check, of distinct witnesses, none confirmed (verification.h)
  bool to_coordinator = false;  // handed to the coordinator to check

  bool answered_by(const Witness& witness) const {
    return std::any_of(answers.begin(), answers.end(), [&](const Answer& a) { return a.vouched_by() == witness; });
  }
};

}  // namespace poet
