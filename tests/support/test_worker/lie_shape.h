#pragma once
// Which answers a lying worker gets wrong: the shapes of liar that the coordinator's verification must catch. Pure:
// the choice is a function of the job and batch ids and of how many answers went before, so a test can predict it.

#include <cstdint>

namespace poet::test_worker {

struct LieShape {
  int64_t honest_jobs = 0;  // answers its first this many jobs honestly (sitting out a probation)
  double fraction = 1;      // then lies on this fraction of its jobs, drawn from the job id
  // and only where a public rule of the batch and job ids (the kind a coordinator without a secret might use,
  // at 5 %) predicts no check
  bool where_predicted_unchecked = false;
};

// Decides, answer by answer, whether the answer is a lie. Call it once for each answer, in the order they are sent.
class Liar {
 public:
  explicit Liar(LieShape shape) : shape_(shape) {}
  bool lies_on(uint64_t job_id, uint64_t batch_id);

 private:
  LieShape shape_;
  int64_t answered_ = 0;
};

}  // namespace poet::test_worker
