#include "coordinator/dispatch/job_queue.h"

#include <algorithm>

namespace poet {
namespace {

// The queued jobs a worker looks through for one it may take; the rest wait their turn.
constexpr size_t kQueueScan = 4096;

}  // namespace

bool OpenJob::held_by(const WorkerId& worker) const {
  return std::any_of(leases.begin(), leases.end(), [&](const Lease& l) { return l.worker == worker; });
}

Millis OpenJob::newest_lease() const {
  Millis newest = 0;
  for (const Lease& l : leases) newest = std::max(newest, l.since);
  return newest;
}

void JobQueue::clear() {  // job ids go on across batches: a late result of an earlier batch names no open job
  jobs_.clear();
  queue_.clear();
  job_times_.clear();
  backup_after_ = 0;
}

OpenJob& JobQueue::add(size_t begin, size_t end, int deaths) {
  OpenJob job;
  job.id = next_id_++;
  job.begin = begin;
  job.end = end;
  job.deaths = deaths;
  return jobs_.emplace(job.id, std::move(job)).first->second;
}

void JobQueue::forget_holder(const WorkerId& worker) {
  for (auto& [id, job] : jobs_) job.taken_back.erase(worker);
}

JobQueue::HandIn JobQueue::hand_in(uint64_t id, const WorkerId& worker, Millis now) {
  OpenJob* job = find(id);
  if (job == nullptr) return {};
  const auto lease =
      std::find_if(job->leases.begin(), job->leases.end(), [&](const Lease& l) { return l.worker == worker; });
  const bool held = lease != job->leases.end();
  const bool taken_back = job->taken_back.erase(worker) > 0;
  if (!held && !taken_back) return {};
  const Millis took = held ? now - lease->since : 0;
  if (held) job->leases.erase(lease);
  return {job, held, took};
}

void JobQueue::enqueue(const std::vector<uint64_t>& ids, bool front) {
  for (const uint64_t id : ids) jobs_.at(id).queued = true;
  if (front) {
    queue_.insert(queue_.begin(), ids.begin(), ids.end());
  } else {
    queue_.insert(queue_.end(), ids.begin(), ids.end());
  }
}

void JobQueue::enqueue_front(OpenJob& job) {
  if (job.queued) return;
  job.queued = true;
  queue_.push_front(job.id);
}

void JobQueue::erase(uint64_t id) {
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) return;
  if (it->second.queued)
    if (const auto q = std::find(queue_.begin(), queue_.end(), id); q != queue_.end()) queue_.erase(q);
  jobs_.erase(it);
}

OpenJob* JobQueue::find(uint64_t id) {
  const auto it = jobs_.find(id);
  return it == jobs_.end() ? nullptr : &it->second;
}

void JobQueue::finished_in(Millis took) {
  job_times_.add(took);
  backup_after_ = std::max(timings_.backup_min_ms, static_cast<Millis>(timings_.backup_factor * job_times_.median()));
}

OpenJob* JobQueue::take_queued(const Pick& pick) {
  size_t scanned = 0;
  for (auto it = queue_.begin(); it != queue_.end() && scanned < kQueueScan; ++it, ++scanned) {
    OpenJob& job = jobs_.at(*it);
    if (!pick(job)) continue;
    queue_.erase(it);
    job.queued = false;
    return &job;
  }
  return nullptr;
}

OpenJob* JobQueue::fewest_holders(const Pick& pick) {
  OpenJob* fewest = nullptr;
  for (auto& [id, job] : jobs_) {
    if (job.queued || job.leases.empty() || !pick(job)) continue;
    if (fewest == nullptr || job.leases.size() < fewest->leases.size()) fewest = &job;
  }
  return fewest;
}

OpenJob* JobQueue::held_only_by(const std::function<bool(const WorkerId&)>& holder_unproven, const Pick& pick) {
  for (auto& [id, job] : jobs_) {
    // (trials pile onto a job beyond max_leases: they do not count, the first proven holder does)
    if (job.queued || job.leases.empty()) continue;
    const bool only =
        std::all_of(job.leases.begin(), job.leases.end(), [&](const Lease& l) { return holder_unproven(l.worker); });
    if (only && pick(job)) return &job;
  }
  return nullptr;
}

OpenJob* JobQueue::backup(Millis now, const Pick& pick) {
  const Millis lease = lease_ms();
  OpenJob* oldest = nullptr;
  Millis oldest_since = 0;
  for (auto& [id, job] : jobs_) {
    if (job.queued || job.leases.empty() || job.leases.size() >= static_cast<size_t>(timings_.max_leases)) continue;
    const Millis newest = job.newest_lease();
    if (now - newest < lease || !pick(job)) continue;
    if (oldest == nullptr || newest < oldest_since) {
      oldest = &job;
      oldest_since = newest;
    }
  }
  if (oldest != nullptr) backups_ += 1;
  return oldest;
}

bool JobQueue::any_overdue(Millis now) const {
  if (timings_.backup_factor <= 0) return false;
  const Millis lease = lease_ms();
  return std::any_of(jobs_.begin(), jobs_.end(), [&](const auto& entry) {
    const OpenJob& job = entry.second;
    if (job.queued || job.leases.empty() || job.leases.size() >= static_cast<size_t>(timings_.max_leases)) return false;
    return std::all_of(job.leases.begin(), job.leases.end(), [&](const Lease& l) { return now - l.since >= lease; });
  });
}

std::vector<std::pair<uint64_t, WorkerId>> JobQueue::take_back_expired(
    Millis now, const std::function<bool(const WorkerId&)>& may_take_back) {
  const Millis lease = lease_ms();
  std::vector<std::pair<uint64_t, WorkerId>> taken;
  for (auto& [id, job] : jobs_) {
    const size_t before = job.leases.size();
    std::erase_if(job.leases, [&](const Lease& l) {
      if (now - l.since < lease || !may_take_back(l.worker)) return false;
      job.taken_back.insert(l.worker);
      taken.emplace_back(id, l.worker);
      return true;
    });
    if (job.leases.size() == before) continue;
    leases_expired_ += static_cast<int64_t>(before - job.leases.size());
    if (job.leases.empty()) enqueue_front(job);
  }
  return taken;
}

}  // namespace poet
