#include "tests/support/test_worker/lie_shape.h"

#include "simulation/rng.h"

namespace poet::test_worker {
namespace {

double unit(uint64_t key) { return static_cast<double>(key >> 11) * 0x1.0p-53; }

}  // namespace

bool Liar::lies_on(uint64_t job_id, uint64_t batch_id) {
  if (answered_++ < shape_.honest_jobs) return false;
  if (shape_.fraction < 1 && unit(stream_key(0, "lie", {job_id})) >= shape_.fraction) return false;
  return !shape_.where_predicted_unchecked || unit(stream_key(1, "verify", {batch_id, job_id})) >= 0.05;
}

}  // namespace poet::test_worker
