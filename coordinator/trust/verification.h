#pragma once
// What is verified — a judge, and the count of what it found right: which jobs are chosen for a check (drawn from a
// secret the workers never see), whose answers need a second one (a chosen job's, or any answer of a worker on
// probation), and what the answers held for a job say once another comes in — taken, held for another witness,
// one or more found wrong, or left to the coordinator. It knows no queue and no sockets; WorkerTrust acts on its
// verdicts.
//
// Independent witnesses. An answer counts as evidence only as far as the party behind it is independent of the
// others, and no party counts twice:
// 1. A witness is a CURVE key, or without CURVE a connection. Answers of one witness never confirm or refute each
//    other: a second answer of a witness already held is not evidence, and is not kept.
// 2. Two answers confirm each other when they are alike, of two witnesses, and not both given on probation.
// 3. An answer given on probation never refutes another: where the answers held differ, only an answer given past
//    probation by a witness not among them, a local worker's, or the coordinator's own computation decides. The
//    side an answer confirms is taken, and the other answers held are found wrong.
// 4. Three answers held and none confirmed: the coordinator's own computation decides.
// 5. Held answers keep the witness and standing they were given with, so that an identity gone (its connection
//    closed, a new one opened) is confirmed only as rule 2 says, by another witness.
// Without CURVE a witness costs a connection, so these rules hold one connection to one vote, not one party: one
// party that passes probation on several connections may confirm its own answers (docs/service.md says what an
// open port can and cannot guarantee).

#include <cstddef>
#include <cstdint>
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
  Witness witness = {};    // who vouches for it (rule 1); empty: the worker's connection alone
  bool probation = false;  // given on probation (rules 2 and 3)

  const Witness& vouched_by() const { return witness.empty() ? worker : witness; }
};

// Whether the answers held differ (a dispute: rule 3).
bool disputed(const std::vector<Answer>& held);

// What an answer to a job held for a check means.
struct Verdict {
  enum class Kind {
    kTake,         // the results stand: take them from `credited`
    kHold,         // the job waits for another witness's answer (`keep`: the answer is held with it)
    kCoordinator,  // three answers held and none confirmed (rule 4): the coordinator decides; the answer is held
  };
  Kind kind = Kind::kHold;
  bool keep = true;              // kHold: false for a witness already held (rule 1)
  WorkerId credited;             // kTake: whose answer the results are
  std::vector<WorkerId> passed;  // answers found right
  std::vector<WorkerId> wrong;   // answers found wrong: their workers are refused before the results are taken
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

  // Another answer to a job with `held` answers awaiting a check (of distinct witnesses, none confirmed), by the
  // rules above; `incoming_local`: a local worker's, which decides at once.
  Verdict judge(const std::vector<Answer>& held, const Answer& incoming, bool incoming_local);
  // Whether only a witness past probation may answer a job holding these answers: all were given on probation (rule
  // 2), or they differ (rule 3).
  static bool needs_witness_past_probation(const std::vector<Answer>& held);
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
