#include "python/thread_team.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace poet {
namespace {

// How long a thread spins for the next step (or for the team to finish) before it sleeps. Waking a sleeping thread
// on another CPU takes tens of microseconds on a virtual machine, a step of 8 walkers a few hundred: spinning
// through the gap between two steps (the caller's policy, numpy) keeps the wake-up off each step.
constexpr auto kSpinFor = std::chrono::microseconds(200);

void pause() {
#if defined(__x86_64__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

// Spins until done() or kSpinFor has passed; done()'s last answer.
template <class Done>
bool spin_until(Done done) {
  const auto until = std::chrono::steady_clock::now() + kSpinFor;
  for (int i = 0;; ++i) {
    if (done()) return true;
    if (i % 64 == 63 && std::chrono::steady_clock::now() > until) return done();
    pause();
  }
}

}  // namespace

ThreadTeam::ThreadTeam(int threads) : threads_(std::max(threads, 1)) { start(); }

ThreadTeam::~ThreadTeam() {
  if (pid_ != getpid()) {  // a forked child: the helpers are the parent's; nothing here to stop or join
    abandon();
    return;
  }
  shared_->quit = true;
  shared_->generation.fetch_add(1, std::memory_order_release);
  shared_->generation.notify_all();
  for (std::thread& t : helpers_) t.join();
}

void ThreadTeam::start() {
  pid_ = getpid();
  shared_ = std::make_unique<Shared>();
  shared_->shares = std::vector<Shared::Share>(static_cast<size_t>(threads_));
  helpers_.clear();
  for (int t = 1; t < threads_; ++t) helpers_.emplace_back(help, std::ref(*shared_), t);
}

// A forked child holds a copy of the parent's team without its threads (and maybe a lock taken mid-run): the copy
// is left as it is, not even destroyed (destroying a std::thread that was not joined ends the process, and joining
// or detaching one that does not exist here is undefined).
void ThreadTeam::abandon() {
  (void)shared_.release();
  (void)new std::vector<std::thread>(std::move(helpers_));
  helpers_.clear();
}

void ThreadTeam::work(Shared& shared, int member) {
  const size_t members = shared.shares.size();
  for (size_t k = 0; k < members; ++k) {
    Shared::Share& share = shared.shares[(static_cast<size_t>(member) + k) % members];
    for (int i = share.next.fetch_add(1); i < share.end; i = share.next.fetch_add(1)) {
      try {
        (*shared.fn)(i);
      } catch (...) {
        std::lock_guard lock(shared.error_mutex);
        if (!shared.error) shared.error = std::current_exception();
        for (Shared::Share& s : shared.shares) s.next = s.end;  // stop handing out work
      }
    }
  }
}

void ThreadTeam::help(Shared& shared, int member) {
  uint32_t seen = 0;
  while (true) {
    if (!spin_until([&] { return shared.generation.load(std::memory_order_acquire) != seen; }))
      shared.generation.wait(seen, std::memory_order_acquire);  // sleeps on a futex
    seen = shared.generation.load(std::memory_order_acquire);
    if (shared.quit) return;
    work(shared, member);
    if (shared.pending.fetch_sub(1, std::memory_order_acq_rel) == 1) shared.pending.notify_one();
  }
}

void ThreadTeam::run(int n, const std::function<void(int)>& fn) {
  if (pid_ != getpid()) {
    abandon();
    start();
  }
  Shared& shared = *shared_;
  shared.fn = &fn;
  const int members = static_cast<int>(shared.shares.size());
  for (int m = 0; m < members; ++m) {
    shared.shares[static_cast<size_t>(m)].next = static_cast<int>(int64_t{n} * m / members);
    shared.shares[static_cast<size_t>(m)].end = static_cast<int>(int64_t{n} * (m + 1) / members);
  }
  shared.error = nullptr;
  shared.pending.store(static_cast<int>(helpers_.size()), std::memory_order_relaxed);
  shared.generation.fetch_add(1, std::memory_order_release);
  shared.generation.notify_all();
  work(shared, 0);
  spin_until([&] { return shared.pending.load(std::memory_order_acquire) == 0; });
  for (int left = shared.pending.load(std::memory_order_acquire); left != 0;
       left = shared.pending.load(std::memory_order_acquire))
    shared.pending.wait(left, std::memory_order_acquire);
  if (shared.error) std::rethrow_exception(shared.error);
}

}  // namespace poet
