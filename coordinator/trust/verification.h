#pragma once
// What is verified — a judge, and the count of what it found right: which jobs are chosen for a check (drawn from a
// secret the workers never see), whose answers need a second one (a chosen job's, or any answer of a worker on
// probation), and what the answers held for a job say once another comes in — taken, held for another worker, or one of
// two found wrong. It knows no queue and no sockets; WorkerTrust acts on its verdicts.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "coordinator/trust/standing.h"
#include "simulation/rollout.h"

namespace poet {

// Bit for bit: every worker of one build computes exactly the same numbers.
bool same_results(const std::vector<RolloutResult>& a, const std::vector<RolloutResult>& b);

// A worker's results for a job, held until another answer agrees or decides.
struct Answer {
  WorkerId worker;
  std::vector<RolloutResult> results;
};

// What an answer to a job held for a check means.
struct Verdict {
  enum class Kind {
    kTake,       // the results stand: take them from `credited`
    kHold,       // keep the answer; the job waits for another worker's
    kThreeWays,  // three answers, all different: the workers do not compute alike
  };
  Kind kind = Kind::kHold;
  WorkerId credited;              // kTake: whose answer the results are
  std::vector<WorkerId> passed;   // answers found right
  std::optional<WorkerId> wrong;  // an answer found wrong: its worker is refused before the results are taken
};

// The coordinator's own results against the answers held: who agreed, who did not.
struct CoordinatorVerdict {
  std::vector<WorkerId> passed;
  std::vector<WorkerId> wrong;
};

class Verification {
 public:
  // fraction: of the jobs answered by workers that are not local, also run on a second (0: none); secret: which
  // ones; probation_checks: answers of a new worker checked, all of them, before the fraction applies.
  Verification(double fraction, uint64_t secret, int probation_checks)
      : fraction_(fraction), secret_(secret), probation_checks_(probation_checks) {}

  bool enabled() const { return fraction_ > 0; }
  // Whether the job of tasks [begin, end) of `batch` is chosen for a check.
  bool chosen(uint64_t batch, size_t begin, size_t end) const;
  bool on_probation(const Standing& worker) const;
  // Whether this worker's answer to a job is judged against another's rather than taken: an answer is held for the
  // job already (it is compared with the next, whoever gives it: the only check a newcomer gets when the proven
  // worker that backs its job up answers second), or the job was chosen or the worker is on probation and the
  // worker is not local.
  bool needs_check(bool job_chosen, const Standing& worker, bool answers_held) const;
  // An answer taken without a check is final at once only from a local worker, or with verification off.
  bool final_unchecked(const Standing& worker) const { return !enabled() || worker.local; }

  // Another answer to a job with `held` answers awaiting a check (none, one, or two that differ).
  Verdict judge(const std::vector<Answer>& held, const Answer& incoming, bool incoming_local);
  // The coordinator's results for a job against its held answers.
  CoordinatorVerdict settle(const std::vector<Answer>& held, const std::vector<RolloutResult>& results);

  int64_t verified() const { return verified_; }                      // answers found right
  int64_t coordinator_checks() const { return coordinator_checks_; }  // jobs settled by the coordinator's answer

 private:
  double fraction_;
  uint64_t secret_;
  int probation_checks_;
  int64_t verified_ = 0;
  int64_t coordinator_checks_ = 0;
};

}  // namespace poet
