// The remote evaluator's own cost against the work it hands out: (a) how many rollout results per second its
// socket thread hands out and takes back when workers answer at once, next to what 256 workers on the shortest
// episodes ask of it; (b) one ES step on two poet-worker processes against the thread evaluator on two threads,
// in the same run. Run: build/bench/dispatch_bench (see bench/README.md).

#include <benchmark/benchmark.h>
#include <pthread.h>
#include <sched.h>
#include <spdlog/spdlog.h>
#include <sys/epoll.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>
#include <zmq.hpp>

#include "common/program/build_fingerprint.h"
#include "coordinator/dispatch/local_workers.h"
#include "coordinator/evaluator/local_evaluator.h"
#include "coordinator/evaluator/remote_evaluator.h"
#include "engine/rollout_batch.h"
#include "es_step_fixture.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/es/optimizer.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"
#include "wire.pb.h"
#include "worker/worker_session.h"

namespace poet {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// CPU seconds of the calling thread: what an episode costs a worker, less disturbed by other processes than wall
// time (though in a VM, time the host takes from the vCPU still counts).
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// ---- where threads run, and how long they ran

std::vector<int> allowed_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::vector<int> cpus;
  if (sched_getaffinity(0, sizeof set, &set) != 0) return cpus;
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
    if (CPU_ISSET(cpu, &set)) cpus.push_back(cpu);
  return cpus;
}

void pin_this_thread(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

// Restores the calling thread's CPU mask on scope exit: every benchmark runs on the main thread, and a thread
// inherits the mask of the thread that starts it.
class CpuMaskGuard {
 public:
  CpuMaskGuard() { pthread_getaffinity_np(pthread_self(), sizeof saved_, &saved_); }
  ~CpuMaskGuard() { pthread_setaffinity_np(pthread_self(), sizeof saved_, &saved_); }
  CpuMaskGuard(const CpuMaskGuard&) = delete;
  CpuMaskGuard& operator=(const CpuMaskGuard&) = delete;

 private:
  cpu_set_t saved_;
};

std::set<pid_t> process_threads() {
  std::set<pid_t> out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task", ec))
    out.insert(static_cast<pid_t>(std::stol(entry.path().filename().string())));
  return out;
}

std::set<pid_t> minus(std::set<pid_t> a, const std::set<pid_t>& b) {
  for (pid_t t : b) a.erase(t);
  return a;
}

// Nanoseconds these threads have spent on a CPU (the scheduler's own count, not sampled ticks).
int64_t cpu_ns(const std::set<pid_t>& threads) {
  int64_t total = 0;
  for (pid_t t : threads) {
    std::ifstream in("/proc/self/task/" + std::to_string(t) + "/schedstat");
    int64_t ns = 0;
    if (in >> ns) total += ns;
  }
  return total;
}

// ---- workers that answer at once

// `count` workers in this process that answer every Job at once with one plausible result per task, so that only
// the coordinator's side of the protocol costs anything. Each speaks through a WorkerSession, poet-worker's own
// side of the protocol (Hello, a Heartbeat after Welcome, a Result per Job, Heartbeats when idle); in place of its
// job runner the results are made up on the spot. One DEALER socket each, all served by one thread (pinned to
// `cpu` when ≥ 0) with a ZeroMQ context of its own.
class InstantWorkers {
 public:
  InstantWorkers(std::string endpoint, int count, int cpu)
      : endpoint_(std::move(endpoint)), count_(count), cpu_(cpu), thread_([this] { run(); }) {}
  ~InstantWorkers() {
    stop_ = true;
    thread_.join();
  }
  InstantWorkers(const InstantWorkers&) = delete;
  InstantWorkers& operator=(const InstantWorkers&) = delete;

  // Waits until every worker has its Welcome; false after `limit`, or when a session ended or lost the
  // coordinator (a Refused, a Shutdown, silence past the liveness window).
  bool wait_welcomed(std::chrono::milliseconds limit) const {
    const auto until = Clock::now() + limit;
    while (welcomed_ < count_ && !failed_ && Clock::now() < until) std::this_thread::sleep_for(5ms);
    return welcomed_ == count_;
  }
  int64_t jobs() const { return jobs_; }
  // Starts timing a batch: first_job_seconds() is then how long after this call its first Job arrived.
  void arm() {
    first_job_ns_ = 0;
    armed_at_ = Clock::now();
  }
  double first_job_seconds() const {
    const int64_t ns = first_job_ns_;
    return ns == 0 ? 0 : 1e-9 * double(ns - armed_at_.load().time_since_epoch().count());
  }

 private:
  struct Peer {
    zmq::socket_t socket;
    worker::WorkerSession session;
    bool welcomed = false;
  };

  // What the session asks for: its messages sent, its jobs answered at once (through the session, as the
  // runner's outcomes are).
  void perform(Peer& peer, const worker::Actions& actions) {
    for (const wire::WorkerMessage& message : actions.send) {
      message.SerializeToString(&buffer_);
      peer.socket.send(zmq::buffer(buffer_), zmq::send_flags::none);
    }
    if (!peer.welcomed && peer.session.state() == worker::SessionState::kWelcomed) {
      peer.welcomed = true;
      ++welcomed_;
    }
    if (actions.exit_code || actions.close_socket) failed_ = true;
    for (const worker::WorkerJob& job : actions.run) {
      worker::JobOutcome outcome{job.job_id, {}, std::nullopt};
      outcome.results.resize(job.tasks.size());
      for (size_t t = 0; t < job.tasks.size(); ++t) {
        outcome.results[t].total_reward = -100.0 + double(t);
        outcome.results[t].steps = 60;
        outcome.results[t].fell = true;
      }
      perform(peer, peer.session.on_job_finished(outcome, worker::Clock::now()));
      ++jobs_;
      if (first_job_ns_ == 0) first_job_ns_ = Clock::now().time_since_epoch().count();
    }
  }

  // Reads and answers everything the socket holds. ZMQ_FD only says "look at ZMQ_EVENTS", and any send may
  // swallow the notice of a message that arrived meanwhile, so this asks ZMQ_EVENTS again until it says no.
  void drain(Peer& peer) {
    while (peer.socket.get(zmq::sockopt::events) & ZMQ_POLLIN) {
      zmq::message_t frame;
      while (peer.socket.recv(frame, zmq::recv_flags::dontwait))
        perform(peer, peer.session.on_frame(frame.to_string_view(), worker::Clock::now()));
    }
  }

  void run() {
    if (cpu_ >= 0) pin_this_thread(cpu_);
    zmq::context_t context(1);  // started here, so its I/O thread shares this thread's CPU
    // epoll over the sockets' notification descriptors: zmq_poll would ask every socket on every call, a system
    // call each, which at 256 sockets costs the workers more than the coordinator it is meant to measure
    const int epoll = epoll_create1(EPOLL_CLOEXEC);
    std::vector<Peer> peers;
    peers.reserve(static_cast<size_t>(count_));
    for (int i = 0; i < count_; ++i) {
      worker::SessionSettings settings;
      settings.threads = 1;
      settings.name = "instant-" + std::to_string(i);
      Peer& peer =
          peers.emplace_back(Peer{zmq::socket_t(context, zmq::socket_type::dealer), worker::WorkerSession(settings)});
      peer.socket.set(zmq::sockopt::linger, 0);
      peer.socket.connect(endpoint_);
      epoll_event event{};
      event.events = EPOLLIN;
      event.data.u32 = static_cast<uint32_t>(i);
      epoll_ctl(epoll, EPOLL_CTL_ADD, peer.socket.get(zmq::sockopt::fd), &event);
      perform(peer, peer.session.start(worker::Clock::now()));  // the Hello, queued until the connection is up
    }
    std::vector<epoll_event> ready(static_cast<size_t>(count_));
    Clock::time_point last_tick = Clock::now();
    while (!stop_) {
      const int n = epoll_wait(epoll, ready.data(), count_, 5);
      for (int k = 0; k < n; ++k) drain(peers[ready[static_cast<size_t>(k)].data.u32]);
      // heartbeats while idle (between batches); the sessions are asked every few ms rather than on every wake-up
      const auto now = Clock::now();
      if (now - last_tick < 5ms) continue;
      last_tick = now;
      for (Peer& peer : peers) {
        if (now < peer.session.next_deadline()) continue;
        perform(peer, peer.session.on_tick(now));
        drain(peer);
      }
    }
    close(epoll);
  }

  const std::string endpoint_;
  const int count_;
  const int cpu_;
  std::atomic<bool> stop_{false};
  std::atomic<int> welcomed_{0};
  std::atomic<bool> failed_{false};
  std::atomic<int64_t> jobs_{0};
  std::atomic<int64_t> first_job_ns_{0};  // steady clock, of the first Job since arm()
  std::atomic<Clock::time_point> armed_at_{};
  std::string buffer_;  // the serving thread's own
  std::thread thread_;  // last: starts once the members above exist
};

// ---- (a) dispatch capacity

constexpr int kPerturbationsPerStep = 256;  // the paper's: 512 rollouts per ES step

// `steps` ES steps of the paper's size, one θ each (shared by its 512 tasks), as the engine builds them.
std::vector<RolloutTask> es_batch(int steps) {
  std::vector<RolloutTask> tasks;
  const EnvDef env{*named_course("r1"), 17};
  for (int s = 0; s < steps; ++s) {
    RandomStream init(stream_key(2024, "bench-dispatch-theta", {static_cast<uint64_t>(s)}));
    const SharedParams theta = share(random_params(init, 0.1));
    for (int i = 0; i < kPerturbationsPerStep; ++i) {
      const uint64_t key = stream_key(2024, "bench-dispatch", {static_cast<uint64_t>(s), static_cast<uint64_t>(i)});
      for (int sign : {1, -1}) {
        RolloutTask task;
        task.theta = theta;
        task.perturbation = Perturbation{key, sign, 0.1};
        task.env = env;
        tasks.push_back(std::move(task));
      }
    }
  }
  return tasks;
}

// The shortest episodes a run hands out: random policies (θ ~ N(0, 0.1²), as every run's first pair starts), with
// the reference's initial push, on the flat and the hard course. Each episode is timed alone in this thread's CPU
// time; the one of fewest steps and the median one are then timed 15 times more, and their median is the figure
// (a single episode of a few milliseconds moves by tens of per cent on a shared machine).
// needed_results/s: what 256 single-thread workers all running the shortest episode ask of the coordinator.
void BM_ShortestEpisodes(benchmark::State& state) {
  std::vector<RolloutTask> tasks;
  for (const char* course : {"flat", "hard"}) {
    for (uint64_t i = 0; i < 24; ++i) {
      RandomStream init(stream_key(2024, "bench-short-episodes", {i}));
      RolloutTask task;
      task.theta = share(random_params(init, 0.1));
      task.env = EnvDef{*named_course(course), 17};
      tasks.push_back(std::move(task));
    }
  }
  const auto median_seconds = [](const RolloutTask& task) {
    std::vector<double> seconds;
    for (int k = 0; k < 15; ++k) {
      const double t0 = thread_cpu_seconds();
      benchmark::DoNotOptimize(run_task(task).total_reward);
      seconds.push_back(thread_cpu_seconds() - t0);
    }
    std::sort(seconds.begin(), seconds.end());
    return seconds[seconds.size() / 2];
  };
  std::vector<int> steps;
  double all_seconds = 0, shortest_s = 0, median_s = 0;
  size_t shortest = 0, median = 0;
  for (auto _ : state) {
    steps.clear();
    all_seconds = 0;
    for (const RolloutTask& task : tasks) {
      const double t0 = thread_cpu_seconds();
      steps.push_back(run_task(task).steps);
      all_seconds += thread_cpu_seconds() - t0;
    }
    std::vector<size_t> order(tasks.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return steps[x] < steps[y]; });
    shortest = order.front();
    median = order[order.size() / 2];
    shortest_s = median_seconds(tasks[shortest]);
    median_s = median_seconds(tasks[median]);
  }
  int64_t total_steps = 0;
  for (int n : steps) total_steps += n;
  state.counters["shortest_steps"] = steps[shortest];
  state.counters["shortest_ms"] = 1e3 * shortest_s;
  state.counters["median_steps"] = steps[median];
  state.counters["median_ms"] = 1e3 * median_s;
  state.counters["us/step"] = 1e6 * all_seconds / double(total_steps);
  state.counters["needed_results/s"] = 256 / shortest_s;
}
// Registered first, so that it runs in a fresh process as a worker does: once the other rows have grown the heap,
// glibc stops returning freed memory to the system between episodes, and the same episode costs some 25 % less
// (fewer page faults).
BENCHMARK(BM_ShortestEpisodes)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// Results per second through a RemoteEvaluator whose `workers` workers answer at once; batches of `tasks` tasks
// (512: one ES step; 10,240: twenty, a paper-sized iteration). The coordinator's threads (its socket thread, its
// ZeroMQ I/O thread, and the caller of evaluate) share one CPU; the workers and their I/O thread the other.
void BM_DispatchCapacity(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);
  const int workers = static_cast<int>(state.range(0));
  const std::vector<RolloutTask> tasks = es_batch(static_cast<int>(state.range(1)) / (2 * kPerturbationsPerStep));

  CpuMaskGuard mask;
  const std::vector<int> cpus = allowed_cpus();
  const bool pinned = cpus.size() >= 2;
  if (pinned) pin_this_thread(cpus[0]);
  const std::set<pid_t> before = process_threads();
  DispatchSettings settings;  // fingerprint 0: the instant workers have none
  Expected<std::unique_ptr<RemoteEvaluator>> bound = RemoteEvaluator::bind("tcp://127.0.0.1:*", settings, {});
  if (!bound) {
    state.SkipWithError(bound.error().c_str());
    return;
  }
  const std::unique_ptr<RemoteEvaluator> remote = std::move(*bound);
  std::set<pid_t> coordinator = minus(process_threads(), before);
  coordinator.insert(gettid());  // the caller of evaluate, as the engine's thread is in poet-coordinator
  InstantWorkers instant(remote->endpoint(), workers, pinned ? cpus[1] : -1);
  if (!instant.wait_welcomed(20s)) {
    state.SkipWithError("the instant workers were not all welcomed");
    return;
  }
  const std::set<pid_t> worker_side = minus(minus(process_threads(), before), coordinator);

  Evaluator& evaluator = *remote;
  try {
    evaluator.evaluate(tasks);  // once untimed: every worker known and ready, buffers grown
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const int64_t jobs0 = instant.jobs();
  const int64_t coordinator_ns0 = cpu_ns(coordinator), workers_ns0 = cpu_ns(worker_side);
  double start_delays = 0;
  const auto t0 = Clock::now();
  for (auto _ : state) {
    try {
      instant.arm();
      std::vector<RolloutResult> results = evaluator.evaluate(tasks);
      start_delays += instant.first_job_seconds();
      benchmark::DoNotOptimize(results.data());
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      break;
    }
  }
  const double wall = seconds_since(t0);
  const double coordinator_s = double(cpu_ns(coordinator) - coordinator_ns0) * 1e-9;
  const double workers_s = double(cpu_ns(worker_side) - workers_ns0) * 1e-9;
  const double results = double(state.iterations()) * double(tasks.size());
  const double jobs = double(instant.jobs() - jobs0);
  state.SetItemsProcessed(static_cast<int64_t>(results));
  state.counters["jobs/s"] = benchmark::Counter(jobs, benchmark::Counter::kIsRate);
  state.counters["tasks/job"] = jobs > 0 ? results / jobs : 0;
  // from evaluate() to the first Job at a worker: the socket thread learns of a new batch on its next turn
  state.counters["start_ms"] = 1e3 * start_delays / double(state.iterations());
  state.counters["results/s_running"] = results / (wall - start_delays);
  // how busy each side's CPU was: a coordinator near 1 is the limit; workers near 1 would make them the limit
  state.counters["coord_busy"] = coordinator_s / wall;
  state.counters["workers_busy"] = workers_s / wall;
  state.counters["results/coord_cpu_s"] = coordinator_s > 0 ? results / coordinator_s : 0;
  state.counters["pinned"] = pinned;
}
BENCHMARK(BM_DispatchCapacity)
    ->ArgNames({"workers", "tasks"})
    ->ArgsProduct({{8, 64, 256}, {512}})
    ->Iterations(200)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_DispatchCapacity)
    ->ArgNames({"workers", "tasks"})
    ->ArgsProduct({{8, 64, 256}, {10'240}})
    ->Iterations(10)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The Dispatcher alone, no sockets: the same batches and workers as above, each Job serialized and each Result
// parsed as the socket thread does, so what remains of BM_DispatchCapacity's time is ZeroMQ, the kernel and the
// waiting. thetas/job is how many θ copies travel per job (θ goes to each worker once per batch).
void BM_DispatcherAlone(benchmark::State& state) {
  const int workers = static_cast<int>(state.range(0));
  const std::vector<RolloutTask> tasks = es_batch(static_cast<int>(state.range(1)) / (2 * kPerturbationsPerStep));
  Dispatcher dispatcher(DispatchSettings{});
  wire::Hello hello;
  hello.set_protocol_version(wire::PROTOCOL_VERSION);
  hello.set_threads(1);
  for (int w = 0; w < workers; ++w) {
    const WorkerId id = "w" + std::to_string(w);
    dispatcher.on_hello(id, hello, 0);
    dispatcher.heard_from(id, 0);  // its Heartbeat after Welcome: ready
  }
  int64_t jobs = 0, thetas = 0;
  wire::WorkerMessage reply;
  wire::WorkerMessage parsed;
  wire::CoordinatorMessage job;
  for (auto _ : state) {
    dispatcher.start_batch(tasks);
    while (!dispatcher.batch_done()) {
      const std::vector<Outgoing> out = dispatcher.outgoing(1);
      if (out.empty()) break;
      for (const Outgoing& message : out) {
        if (!message.message.has_job()) continue;
        const std::string bytes = message.frame();  // as RemoteEvaluator::send
        job.ParseFromString(bytes);                 // the worker's side, kept out of the count
        wire::Result* result = reply.mutable_result();
        result->Clear();
        result->set_job_id(job.job().job_id());
        for (int t = 0; t < job.job().tasks_size(); ++t) {
          wire::TaskResult* r = result->add_results();
          r->set_total_reward(-100.0 + t);
          r->set_steps(60);
          r->set_fell(true);
        }
        parsed.ParseFromString(reply.SerializeAsString());  // as RemoteEvaluator::handle
        dispatcher.on_result(message.worker, parsed.result(), 1);
        ++jobs;
        thetas += job.job().thetas_size();
      }
    }
    if (!dispatcher.batch_done()) {
      state.SkipWithError("the dispatcher handed out no job");
      break;
    }
    benchmark::DoNotOptimize(dispatcher.take_results().data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(tasks.size()));
  state.counters["jobs/s"] = benchmark::Counter(double(jobs), benchmark::Counter::kIsRate);
  state.counters["tasks/job"] = jobs > 0 ? double(state.iterations()) * double(tasks.size()) / double(jobs) : 0;
  state.counters["thetas/job"] = jobs > 0 ? double(thetas) / double(jobs) : 0;
}
BENCHMARK(BM_DispatcherAlone)
    ->ArgNames({"workers", "tasks"})
    ->ArgsProduct({{8, 64, 256}, {512, 10'240}})
    ->Unit(benchmark::kMillisecond);

// ---- (b) an ES step on worker processes against threads

struct EsStepOutcome {
  double seconds = 0;
  std::vector<double> theta;  // after the step: equal through either evaluator, or a result differed
};

EsStepOutcome es_step(const EsStepFixture& f, Evaluator& evaluator, uint64_t step) {
  const auto t0 = Clock::now();
  RunCounters counters;
  RolloutBatch batch(f.episodes);
  const size_t handle = f.add_step(batch, step);
  batch.run(evaluator, counters);
  OptimizerState opt = fresh_optimizer(f.es, f.theta.size());
  EsStepOutcome out{0, f.theta};
  adam_step(out.theta, batch.es_outcome(handle, f.es).gradient, opt, f.es);
  decay(opt, f.es);
  out.seconds = seconds_since(t0);
  return out;
}

// The same ES steps, alternately on 2 poet-worker processes (1 thread each) through the RemoteEvaluator and on the
// LocalEvaluator with 2 threads; remote/local is the ratio of their summed wall times.
void BM_EsStepRemoteVsLocal(benchmark::State& state) {
  spdlog::set_level(spdlog::level::warn);
  const EsStepFixture f;
  std::atomic<size_t> connected{0};  // outlives the evaluator, whose socket thread writes it
  DispatchSettings settings;
  settings.heartbeat_ms = 1000;
  settings.liveness_ms = 5000;
  settings.build = {build_fingerprint_digest(), arithmetic_digest(), arithmetic_text()};
  Expected<std::unique_ptr<RemoteEvaluator>> bound = RemoteEvaluator::bind("tcp://127.0.0.1:*", settings, {});
  if (!bound) {
    state.SkipWithError(bound.error().c_str());
    return;
  }
  const std::unique_ptr<RemoteEvaluator> remote = std::move(*bound);
  remote->on_snapshot([&connected](const DispatchView& d) { connected = d.workers.size(); });
  // as --local-workers starts them, without the local token: the workers earn their trust as remote ones do
  const Expected<std::unique_ptr<LocalWorkers>> processes =
      LocalWorkers::start(POET_WORKER_BINARY, remote->endpoint(), 2, 1, "");
  const auto until = Clock::now() + 20s;
  while (processes && connected < 2 && Clock::now() < until) std::this_thread::sleep_for(20ms);
  if (!processes || connected < 2) {
    state.SkipWithError("the two poet-worker processes did not connect (" POET_WORKER_BINARY ")");
    return;
  }
  LocalEvaluator local(2);
  Evaluator& remote_evaluator = *remote;
  double local_s = 0, remote_s = 0;
  uint64_t step = 0;
  for (auto _ : state) {
    try {
      const EsStepOutcome a = es_step(f, local, step % 4);
      const EsStepOutcome b = es_step(f, remote_evaluator, step % 4);
      ++step;
      local_s += a.seconds;
      remote_s += b.seconds;
      if (a.theta != b.theta) {
        state.SkipWithError("the remote step's θ differs from the local step's");
        break;
      }
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      break;
    }
  }
  remote->shutdown_workers("benchmark done");
  if (step == 0) return;
  state.counters["local_ms"] = 1e3 * local_s / double(step);
  state.counters["remote_ms"] = 1e3 * remote_s / double(step);
  state.counters["remote/local"] = remote_s / local_s;
}
BENCHMARK(BM_EsStepRemoteVsLocal)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace
}  // namespace poet
