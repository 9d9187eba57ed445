#pragma once
// Checkpoints kept in memory so that a run can go back to one computed before a worker later found wrong had
// unchecked answers taken (engine/evaluator.h: Withdrawals). Each is a checkpoint file's bytes as saved, with the last
// batch the evaluator had started by then; only those a rollback may still need are kept: the newest, and for each
// worker that may yet be found wrong the newest saved before its first unchecked answer's batch.

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace poet {

struct CheckpointAnchor {
  uint64_t last_batch = 0;  // the batch started last when it was saved (0: none)
  int next_iteration = 0;
  std::string bytes;  // checkpoint.pb's
};

class CheckpointAnchors {
 public:
  // A checkpoint just saved.
  void add(CheckpointAnchor anchor);
  // Keeps the newest and, for each batch in `needed`, the newest saved before that batch started.
  void prune(std::span<const uint64_t> needed);
  // The newest saved before batch `first_bad` started; nullptr when none is kept.
  const CheckpointAnchor* before(uint64_t first_bad) const;
  // Drops those saved after `anchor`: the run goes back to it, and what followed it is computed again.
  void keep_until(const CheckpointAnchor& anchor);
  size_t size() const { return anchors_.size(); }

 private:
  std::vector<CheckpointAnchor> anchors_;  // oldest first
};

}  // namespace poet
