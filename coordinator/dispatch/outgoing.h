#pragma once
// A message for one worker, and its bytes on the wire. A Job's θs travel as fields encoded once per batch and
// shared by every job that carries them, appended to the rest of the Job when the frame is written: a θ is 22 KB,
// and encoding it afresh for each of a batch's hundreds of jobs was most of the coordinator's work per job. The
// frame parses as the plain CoordinatorMessage with the θs in Job.thetas (fields may come in any order).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "coordinator/dispatch/dispatch_view.h"
#include "wire.pb.h"

namespace poet {

struct Outgoing {
  Outgoing() = default;
  explicit Outgoing(WorkerId to, wire::CoordinatorMessage what = {})
      : worker(std::move(to)), message(std::move(what)) {}

  WorkerId worker;
  wire::CoordinatorMessage message;
  // with a Job: its θs, each a Job.thetas field as encoded by encode_theta_field
  std::vector<std::shared_ptr<const std::string>> job_thetas;

  size_t frame_size() const;          // the bytes write_frame writes; computes the message's cached sizes
  void write_frame(char* out) const;  // after frame_size(), with the message unchanged since
  std::string frame() const;          // both, into a string
};

// A Heartbeat; a Refused telling why.
Outgoing heartbeat_to(const WorkerId& to);
Outgoing refusal_to(const WorkerId& to, const std::string& reason);

// One θ as the bytes of a Job.thetas field (tag, length, Theta).
std::string encode_theta_field(uint64_t hash, std::span<const double> values);

}  // namespace poet
