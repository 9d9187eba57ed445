#include "worker/worker_session.h"

#include <gtest/gtest.h>

#include <string>

#include "common/program/build_fingerprint.h"
#include "simulation/envgen/named_courses.h"
#include "simulation/policy/mlp.h"
#include "simulation/rng.h"

namespace poet::worker {
namespace {

using namespace std::chrono_literals;

const TimePoint kT0 = TimePoint{} + 1000s;  // the fake clock's origin

SessionSettings settings() {
  SessionSettings s;
  s.threads = 3;
  s.name = "test-host:42";
  s.max_frame_bytes = 4096;
  return s;
}

wire::CoordinatorMessage welcome(uint32_t heartbeat_ms = 100, uint32_t liveness_ms = 600) {
  wire::CoordinatorMessage m;
  m.mutable_welcome()->set_heartbeat_ms(heartbeat_ms);
  m.mutable_welcome()->set_liveness_ms(liveness_ms);
  return m;
}

wire::CoordinatorMessage heartbeat() {
  wire::CoordinatorMessage m;
  m.mutable_heartbeat();
  return m;
}

std::vector<double> theta(uint64_t seed) {
  RandomStream rng(stream_key(seed, "init"));
  return random_params(rng);
}

wire::Theta theta_message(const std::vector<double>& values) {
  wire::Theta t;
  t.set_hash(theta_hash(values));
  for (double v : values) t.add_values(v);
  return t;
}

wire::Task task_message(uint64_t hash, const std::string& course = "flat") {
  RolloutTask task;
  task.env = EnvDef{*named_course(course), 3};
  task.max_steps = 50;
  task.perturbation = Perturbation{.key = 9, .sign = -1, .sigma = 0.02};
  return to_wire(task, hash);
}

// A welcomed session at kT0.
WorkerSession welcomed() {
  WorkerSession session(settings());
  session.start(kT0);
  session.on_message(welcome(), kT0);
  return session;
}

bool only_heartbeat(const Actions& a) { return a.send.size() == 1 && a.send[0].has_heartbeat(); }

TEST(WorkerSession, HelloCarriesVersionFingerprintThreadsAndName) {
  WorkerSession session(settings());
  const Actions a = session.start(kT0);
  ASSERT_EQ(a.send.size(), 1u);
  ASSERT_TRUE(a.send[0].has_hello());
  const wire::Hello& hello = a.send[0].hello();
  EXPECT_EQ(hello.protocol_version(), static_cast<uint32_t>(wire::PROTOCOL_VERSION));
  EXPECT_EQ(hello.fingerprint_digest(), build_fingerprint_digest());
  EXPECT_EQ(hello.fingerprint(), build_fingerprint());
  EXPECT_EQ(hello.threads(), 3u);
  EXPECT_EQ(hello.name(), "test-host:42");
  EXPECT_EQ(session.state(), SessionState::kGreeting);
  EXPECT_FALSE(a.exit_code);
}

TEST(WorkerSession, HelloRepeatsEverySecondUntilWelcome) {
  WorkerSession session(settings());
  session.start(kT0);
  EXPECT_EQ(session.next_deadline(), kT0 + 1s);
  EXPECT_TRUE(session.on_tick(kT0 + 999ms).send.empty());
  Actions a = session.on_tick(kT0 + 1s);
  ASSERT_EQ(a.send.size(), 1u);
  EXPECT_TRUE(a.send[0].has_hello());
  EXPECT_EQ(session.next_deadline(), kT0 + 2s);

  session.on_message(welcome(), kT0 + 1500ms);
  EXPECT_EQ(session.state(), SessionState::kWelcomed);
  for (auto t = kT0 + 1500ms; t < kT0 + 1900ms; t += 10ms) {
    for (const auto& m : session.on_tick(t).send) EXPECT_FALSE(m.has_hello());
    session.on_message(heartbeat(), t);
  }
}

TEST(WorkerSession, HelloThatCouldNotBeSentIsRetriedSoon) {
  WorkerSession session(settings());
  const Actions a = session.start(kT0);
  session.on_send_failed(a.send[0], kT0);
  EXPECT_EQ(session.next_deadline(), kT0 + 50ms);
  EXPECT_TRUE(session.on_tick(kT0 + 50ms).send[0].has_hello());
  EXPECT_EQ(session.next_deadline(), kT0 + 1050ms);
}

TEST(WorkerSession, WelcomeSetsTheHeartbeatSchedule) {
  WorkerSession session = welcomed();
  EXPECT_EQ(session.heartbeat_interval(), 100ms);
  EXPECT_EQ(session.liveness(), 600ms);
  // the Hello went at kT0: a heartbeat is due 100 ms after it, and again 100 ms after each send
  EXPECT_TRUE(session.on_tick(kT0 + 99ms).send.empty());
  EXPECT_TRUE(only_heartbeat(session.on_tick(kT0 + 100ms)));
  EXPECT_TRUE(session.on_tick(kT0 + 150ms).send.empty());
  EXPECT_EQ(session.next_deadline(), kT0 + 200ms);
  // any message sent counts: a Result at 180 ms puts the next heartbeat at 280 ms
  session.on_message(heartbeat(), kT0 + 180ms);
  session.on_job_finished(JobOutcome{.job_id = 1, .results = {}, .error = std::nullopt}, kT0 + 180ms);
  EXPECT_TRUE(session.on_tick(kT0 + 279ms).send.empty());
  EXPECT_TRUE(only_heartbeat(session.on_tick(kT0 + 280ms)));
}

TEST(WorkerSession, WelcomeIsAnsweredAtOnceWithAHeartbeat) {
  WorkerSession session(settings());
  session.start(kT0);
  // the coordinator sends jobs to a worker only once it has heard from it after its Hello
  EXPECT_TRUE(only_heartbeat(session.on_message(welcome(), kT0 + 5ms)));
  EXPECT_TRUE(session.on_message(welcome(), kT0 + 6ms).send.empty()) << "a second Welcome needs no answer";
}

TEST(WorkerSession, RejoinDropsTheJobsAndSaysHelloAgain) {
  WorkerSession session = welcomed();
  const std::vector<double> values = theta(1);
  wire::CoordinatorMessage job;
  job.mutable_job()->set_job_id(5);
  job.mutable_job()->set_batch_id(1);
  *job.mutable_job()->add_thetas() = theta_message(values);
  *job.mutable_job()->add_tasks() = task_message(theta_hash(values));
  ASSERT_EQ(session.on_message(job, kT0 + 10ms).run.size(), 1u);
  EXPECT_EQ(session.cached_thetas(), 1u);

  wire::CoordinatorMessage rejoin;
  rejoin.mutable_rejoin()->set_reason("restarted");
  const Actions a = session.on_message(rejoin, kT0 + 20ms);
  EXPECT_TRUE(a.abandon_jobs);
  EXPECT_FALSE(a.close_socket) << "the connection is fine: only the coordinator's memory of the worker is gone";
  ASSERT_EQ(a.send.size(), 1u);
  EXPECT_TRUE(a.send[0].has_hello());
  EXPECT_EQ(session.state(), SessionState::kGreeting);
  EXPECT_EQ(session.cached_thetas(), 0u);
  // the job's outcome belongs to the coordinator's earlier life: not sent
  EXPECT_TRUE(
      session.on_job_finished(JobOutcome{.job_id = 5, .results = {}, .error = std::nullopt}, kT0 + 30ms).send.empty());
  // a Rejoin while greeting answers a message sent before the Hello: the Welcome is on its way
  EXPECT_TRUE(session.on_message(rejoin, kT0 + 40ms).send.empty());
  EXPECT_TRUE(only_heartbeat(session.on_message(welcome(), kT0 + 50ms)));
  EXPECT_EQ(session.state(), SessionState::kWelcomed);
}

TEST(WorkerSession, WelcomeTimingsHaveDefaultsAndBounds) {
  EXPECT_EQ(welcome_timings(wire::Welcome()), std::make_pair(Millis(1000), Millis(5000)));
  EXPECT_EQ(welcome_timings(welcome(0, 0).welcome()), std::make_pair(Millis(1000), Millis(5000)));
  EXPECT_EQ(welcome_timings(welcome(1, 1).welcome()), std::make_pair(Millis(10), Millis(20)));
  EXPECT_EQ(welcome_timings(welcome(100, 150).welcome()), std::make_pair(Millis(100), Millis(200)));
  EXPECT_EQ(welcome_timings(welcome(4'000'000'000u, 4'000'000'000u).welcome()),
            std::make_pair(Millis(3'600'000), Millis(7'200'000)));
}

TEST(WorkerSession, SilenceForTheLivenessWindowMeansReconnectWithBackoff) {
  WorkerSession session = welcomed();
  // heartbeats from the coordinator keep it alive
  session.on_message(heartbeat(), kT0 + 500ms);
  EXPECT_EQ(session.on_tick(kT0 + 1099ms).close_socket, false);
  EXPECT_EQ(session.state(), SessionState::kWelcomed);
  // then 600 ms of silence
  Actions lost = session.on_tick(kT0 + 1100ms);
  EXPECT_TRUE(lost.abandon_jobs);
  EXPECT_TRUE(lost.close_socket);
  EXPECT_TRUE(lost.send.empty());
  EXPECT_FALSE(lost.exit_code);
  EXPECT_EQ(session.state(), SessionState::kWaitingToReconnect);
  EXPECT_EQ(session.next_deadline(), kT0 + 1350ms);  // the first backoff: 250 ms
  EXPECT_FALSE(session.on_tick(kT0 + 1349ms).open_socket);
  Actions again = session.on_tick(kT0 + 1350ms);
  EXPECT_TRUE(again.open_socket);
  ASSERT_EQ(again.send.size(), 1u);
  EXPECT_TRUE(again.send[0].has_hello());
  EXPECT_EQ(session.state(), SessionState::kGreeting);

  // welcomed again but lost again at once: the backoff doubles, up to 4 s
  auto t = kT0 + 1350ms;
  for (Millis expected : {500ms, 1000ms, 2000ms, 4000ms, 4000ms}) {
    session.on_message(welcome(), t);
    t += 600ms;
    ASSERT_TRUE(session.on_tick(t).close_socket);
    // the reconnection, unless the still-trying line (2 s after the loss) comes first
    EXPECT_EQ(session.next_deadline() - t, std::min(expected, Millis(2000)));
    EXPECT_FALSE(session.on_tick(t + expected - 1ms).open_socket);
    t += expected;
    ASSERT_TRUE(session.on_tick(t).open_socket);
  }
  // a connection that lives a whole liveness window resets it
  session.on_message(welcome(), t);
  session.on_message(heartbeat(), t + 500ms);
  session.on_tick(t + 600ms);
  EXPECT_EQ(session.backoff(), 250ms);
}

TEST(WorkerSession, AnyFrameCountsAsLife) {
  WorkerSession session = welcomed();
  session.on_frame("garbage that is no message", kT0 + 500ms);
  EXPECT_FALSE(session.on_tick(kT0 + 1000ms).close_socket);
  EXPECT_TRUE(session.on_tick(kT0 + 1100ms).close_socket);
}

TEST(WorkerSession, ConnectFailureWaitsWithBackoff) {
  WorkerSession session(settings());
  const Actions a = session.on_connect_failed(kT0);
  EXPECT_TRUE(a.close_socket);
  EXPECT_EQ(session.state(), SessionState::kWaitingToReconnect);
  EXPECT_EQ(session.next_deadline(), kT0 + 250ms);
  EXPECT_TRUE(session.on_tick(kT0 + 250ms).open_socket);
  session.on_connect_failed(kT0 + 250ms);
  EXPECT_EQ(session.next_deadline(), kT0 + 750ms);
}

TEST(WorkerSession, AConnectionThatBringsNoWelcomeIsReplacedByAFreshOne) {
  WorkerSession session(settings());
  session.start(kT0);
  // Hellos every second on the first connection; no Welcome within the greeting timeout: a fresh socket
  for (auto t = kT0; t < kT0 + settings().greeting_timeout; t += 100ms) EXPECT_FALSE(session.on_tick(t).close_socket);
  EXPECT_TRUE(session.on_tick(kT0 + settings().greeting_timeout).close_socket);
  EXPECT_EQ(session.state(), SessionState::kWaitingToReconnect);
  EXPECT_TRUE(session.on_tick(kT0 + settings().greeting_timeout + 250ms).open_socket);
  EXPECT_EQ(session.state(), SessionState::kGreeting);
}

TEST(WorkerSession, WithoutAWelcomeItSaysItIsStillTryingWithGrowingGaps) {
  WorkerSession session(settings());
  session.start(kT0);
  EXPECT_EQ(session.next_deadline(), kT0 + 1000ms);  // the next Hello comes first
  // the lines come 2 s after the start, then after gaps that double up to a minute
  std::vector<Millis> said;
  for (auto t = kT0; t <= kT0 + 190s; t += 10ms) {
    if (const Actions a = session.on_tick(t); a.still_trying) said.push_back(*a.still_trying);
  }
  EXPECT_EQ(said, (std::vector<Millis>{2s, 6s, 14s, 30s, 62s, 122s, 182s}));

  // welcomed: nothing more; lost: the lines count from the loss
  session.on_message(welcome(), kT0 + 200s);
  EXPECT_FALSE(session.on_tick(kT0 + 200s + 500ms).still_trying);
  ASSERT_TRUE(session.on_tick(kT0 + 200s + 600ms).close_socket);
  EXPECT_FALSE(session.on_tick(kT0 + 200s + 2599ms).still_trying);
  const Actions again = session.on_tick(kT0 + 200s + 2600ms);
  ASSERT_TRUE(again.still_trying);
  EXPECT_EQ(*again.still_trying, 2000ms);
}

TEST(WorkerSession, AFailedHandshakeGetsAFreshSocketAfterTheBackoff) {
  WorkerSession session(settings());
  session.start(kT0);
  const Actions failed = session.on_handshake_failed(kT0 + 10ms);
  EXPECT_TRUE(failed.close_socket);
  EXPECT_FALSE(failed.exit_code);
  EXPECT_EQ(session.state(), SessionState::kWaitingToReconnect);
  EXPECT_EQ(session.next_deadline(), kT0 + 260ms);
  const Actions reopened = session.on_tick(kT0 + 260ms);
  EXPECT_TRUE(reopened.open_socket);
  ASSERT_EQ(reopened.send.size(), 1u);
  EXPECT_TRUE(reopened.send[0].has_hello());
  // refused again: the backoff doubles, and the still-trying lines keep their clock
  session.on_handshake_failed(kT0 + 300ms);
  EXPECT_EQ(session.next_deadline(), kT0 + 800ms);
  EXPECT_TRUE(session.on_handshake_failed(kT0 + 400ms).send.empty()) << "already waiting";
  EXPECT_EQ(session.next_deadline(), kT0 + 800ms);
  session.on_tick(kT0 + 800ms);
  const Actions line = session.on_tick(kT0 + 2000ms);
  ASSERT_TRUE(line.still_trying);
  EXPECT_EQ(*line.still_trying, 2000ms);
  // finished: nothing
  session.on_stop(kT0 + 3s, "test");
  EXPECT_FALSE(session.on_handshake_failed(kT0 + 4s).close_socket);
}

TEST(WorkerSession, JobIsDecodedAndHandedToTheRunner) {
  WorkerSession session = welcomed();
  const std::vector<double> values = theta(1);
  const uint64_t hash = theta_hash(values);
  wire::CoordinatorMessage m;
  wire::Job& job = *m.mutable_job();
  job.set_job_id(17);
  job.set_batch_id(4);
  *job.add_thetas() = theta_message(values);
  *job.add_tasks() = task_message(hash, "flat");
  *job.add_tasks() = task_message(hash, "hard");
  const Actions a = session.on_message(m, kT0 + 10ms);
  EXPECT_TRUE(a.send.empty());
  ASSERT_EQ(a.run.size(), 1u);
  const WorkerJob& run = a.run[0];
  EXPECT_EQ(run.job_id, 17u);
  EXPECT_EQ(run.batch_id, 4u);
  ASSERT_EQ(run.tasks.size(), 2u);
  EXPECT_EQ(*run.tasks[0].theta, values);
  EXPECT_EQ(run.tasks[1].env.encoding.name, "hard");
  ASSERT_TRUE(run.tasks[1].perturbation);
  EXPECT_EQ(run.tasks[1].perturbation->sign, -1);
  EXPECT_EQ(run.tasks[1].max_steps, 50);
  EXPECT_EQ(session.cached_thetas(), 1u);

  // the next job of the batch names θ by its hash only
  wire::CoordinatorMessage next;
  next.mutable_job()->set_job_id(18);
  next.mutable_job()->set_batch_id(4);
  *next.mutable_job()->add_tasks() = task_message(hash, "r1");
  const Actions b = session.on_message(next, kT0 + 20ms);
  ASSERT_EQ(b.run.size(), 1u);
  EXPECT_EQ(b.run[0].tasks[0].theta, run.tasks[0].theta);  // the same shared θ
}

// The Result a job is answered with at once, or a failure.
wire::Result refusal(WorkerSession& session, const wire::Job& job) {
  wire::CoordinatorMessage m;
  *m.mutable_job() = job;
  const Actions a = session.on_message(m, kT0 + 10ms);
  EXPECT_TRUE(a.run.empty());
  if (a.send.size() != 1 || !a.send[0].has_result()) {
    ADD_FAILURE() << "no Result";
    return {};
  }
  EXPECT_EQ(a.send[0].result().results_size(), 0);
  return a.send[0].result();
}

TEST(WorkerSession, BadJobsAreAnsweredWithAnErrorNamingTheField) {
  WorkerSession session = welcomed();
  const std::vector<double> values = theta(2);
  const uint64_t hash = theta_hash(values);

  wire::Job short_theta;
  short_theta.set_job_id(1);
  wire::Theta& t = *short_theta.add_thetas();
  t.set_hash(1);
  t.add_values(0.5);
  wire::Result r = refusal(session, short_theta);
  EXPECT_EQ(r.job_id(), 1u);
  EXPECT_EQ(r.error(), "thetas[0].values: 1 values, expected 2804");
  EXPECT_FALSE(r.missing_theta());

  wire::Job wrong_hash;
  wrong_hash.set_job_id(2);
  *wrong_hash.add_thetas() = theta_message(values);
  wrong_hash.mutable_thetas(0)->set_hash(hash + 1);
  EXPECT_EQ(refusal(session, wrong_hash).error(), "thetas[0].hash: does not match the values");

  wire::Job bad_sign;
  bad_sign.set_job_id(3);
  *bad_sign.add_thetas() = theta_message(values);
  *bad_sign.add_tasks() = task_message(hash);
  *bad_sign.add_tasks() = task_message(hash);
  bad_sign.mutable_tasks(1)->set_sign(2);
  r = refusal(session, bad_sign);
  EXPECT_EQ(r.job_id(), 3u);
  EXPECT_EQ(r.error(), "tasks[1].sign: must be +1 or -1 (got 2)");
  EXPECT_FALSE(r.missing_theta());

  wire::Job bad_steps;
  bad_steps.set_job_id(4);
  *bad_steps.add_tasks() = task_message(hash);
  bad_steps.mutable_tasks(0)->set_max_steps(0);
  EXPECT_EQ(refusal(session, bad_steps).error(), "tasks[0].max_steps: must be in [1, 100000] (got 0)");

  wire::Job bad_course;
  bad_course.set_job_id(5);
  *bad_course.add_tasks() = task_message(hash);
  bad_course.mutable_tasks(0)->mutable_env()->set_seed(kMaxEnvSeed);
  EXPECT_TRUE(refusal(session, bad_course).error().starts_with("tasks[0].env.seed"));

  wire::Job no_hash;
  no_hash.set_job_id(6);
  *no_hash.add_tasks() = task_message(hash);
  no_hash.mutable_tasks(0)->clear_theta_hash();
  r = refusal(session, no_hash);
  EXPECT_TRUE(r.error().starts_with("tasks[0].theta_hash")) << r.error();
  EXPECT_FALSE(r.missing_theta());
  EXPECT_EQ(session.drops().total(), 0u);  // refused jobs are answered, not dropped
}

TEST(WorkerSession, UnknownThetaHashIsMissingTheta) {
  WorkerSession session = welcomed();
  const std::vector<double> values = theta(3);
  wire::Job job;
  job.set_job_id(9);
  job.set_batch_id(1);
  *job.add_tasks() = task_message(theta_hash(values));
  const wire::Result r = refusal(session, job);
  EXPECT_EQ(r.job_id(), 9u);
  EXPECT_TRUE(r.missing_theta());
  EXPECT_TRUE(r.error().starts_with("tasks[0].theta_hash: no θ")) << r.error();
}

TEST(WorkerSession, AJobOfANewBatchDropsThePreviousBatchesThetas) {
  WorkerSession session = welcomed();
  const std::vector<double> a = theta(4);
  const std::vector<double> b = theta(5);
  wire::CoordinatorMessage first;
  first.mutable_job()->set_job_id(1);
  first.mutable_job()->set_batch_id(1);
  *first.mutable_job()->add_thetas() = theta_message(a);
  *first.mutable_job()->add_thetas() = theta_message(b);
  *first.mutable_job()->add_tasks() = task_message(theta_hash(a));
  const Actions queued = session.on_message(first, kT0);
  ASSERT_EQ(queued.run.size(), 1u);
  EXPECT_EQ(session.cached_thetas(), 2u);

  wire::Job second;
  second.set_job_id(2);
  second.set_batch_id(2);
  *second.add_tasks() = task_message(theta_hash(a));
  EXPECT_TRUE(refusal(session, second).missing_theta());
  EXPECT_EQ(session.cached_thetas(), 0u);
  // the queued job of batch 1 still holds its θ
  EXPECT_EQ(*queued.run[0].tasks[0].theta, a);
}

TEST(WorkerSession, FinishedJobBecomesAResult) {
  WorkerSession session = welcomed();
  RolloutResult r1;
  r1.total_reward = -12.5;
  r1.steps = 77;
  r1.fell = true;
  RolloutResult r2;
  r2.total_reward = 301.25;
  r2.steps = 1200;
  r2.finished = true;
  Actions a = session.on_job_finished(JobOutcome{.job_id = 5, .results = {r1, r2}, .error = std::nullopt}, kT0);
  ASSERT_EQ(a.send.size(), 1u);
  const wire::Result& result = a.send[0].result();
  EXPECT_EQ(result.job_id(), 5u);
  EXPECT_FALSE(result.has_error());
  ASSERT_EQ(result.results_size(), 2);
  EXPECT_EQ(result.results(0).total_reward(), -12.5);
  EXPECT_EQ(result.results(0).steps(), 77);
  EXPECT_TRUE(result.results(0).fell());
  EXPECT_TRUE(result.results(1).finished());

  a = session.on_job_finished(JobOutcome{.job_id = 6, .results = {}, .error = "tasks[2]: boom"}, kT0);
  EXPECT_EQ(a.send[0].result().error(), "tasks[2]: boom");
  EXPECT_EQ(a.send[0].result().results_size(), 0);

  // after the coordinator is lost, an outcome is not sent anywhere
  session.on_tick(kT0 + 10s);
  EXPECT_TRUE(
      session.on_job_finished(JobOutcome{.job_id = 7, .results = {r1}, .error = std::nullopt}, kT0 + 10s).send.empty());
}

TEST(WorkerSession, HostileFramesAreCountedAndDropped) {
  WorkerSession session(settings());
  session.start(kT0);
  // before Welcome, a Job and a Heartbeat make no sense
  wire::CoordinatorMessage job;
  job.mutable_job()->set_job_id(1);
  EXPECT_TRUE(session.on_message(job, kT0).run.empty());
  EXPECT_TRUE(session.on_frame(heartbeat().SerializeAsString(), kT0).send.empty());
  EXPECT_EQ(session.drops().unexpected, 2u);

  session.on_message(welcome(), kT0);
  const std::string garbage = "\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff\xff";
  EXPECT_TRUE(session.on_frame(garbage, kT0).send.empty());
  EXPECT_EQ(session.drops().unparsable, 1u);
  EXPECT_TRUE(session.on_frame(std::string(4097, 'x'), kT0).send.empty());
  EXPECT_EQ(session.drops().oversized, 1u);
  session.on_frame("", kT0);  // parses as a message with no kind
  session.on_multipart(kT0);
  wire::CoordinatorMessage no_id;
  no_id.mutable_job();
  session.on_message(no_id, kT0);
  EXPECT_EQ(session.drops().unexpected, 5u);
  // a message of a kind from a later protocol (field 99) has no kind this worker knows
  const std::string future = std::string("\x9a\x06\x00", 3);
  session.on_frame(future, kT0);
  EXPECT_EQ(session.drops().unexpected, 6u);
  EXPECT_EQ(session.drops().total(), 8u);
  EXPECT_EQ(session.state(), SessionState::kWelcomed);
}

TEST(WorkerSession, RefusedExits2AndShutdownExits0) {
  WorkerSession refused(settings());
  refused.start(kT0);
  wire::CoordinatorMessage no;
  no.mutable_refused()->set_reason("fingerprint differs");
  Actions a = refused.on_message(no, kT0);
  EXPECT_EQ(a.exit_code, 2);
  EXPECT_EQ(refused.state(), SessionState::kFinished);
  EXPECT_EQ(refused.next_deadline(), TimePoint::max());

  WorkerSession session = welcomed();
  wire::CoordinatorMessage bye;
  bye.mutable_shutdown()->set_reason("run finished");
  a = session.on_message(bye, kT0);
  EXPECT_EQ(a.exit_code, 0);
  EXPECT_TRUE(a.abandon_jobs);
  EXPECT_TRUE(a.send.empty());
}

TEST(WorkerSession, StopSaysGoodbyeWhenWelcomed) {
  WorkerSession session = welcomed();
  Actions a = session.on_stop(kT0, "SIGTERM");
  EXPECT_EQ(a.exit_code, 0);
  EXPECT_TRUE(a.abandon_jobs);
  ASSERT_EQ(a.send.size(), 1u);
  EXPECT_EQ(a.send[0].goodbye().reason(), "SIGTERM");

  WorkerSession greeting(settings());
  greeting.start(kT0);
  a = greeting.on_stop(kT0, "SIGTERM");
  EXPECT_EQ(a.exit_code, 0);
  EXPECT_TRUE(a.send.empty());  // nobody to say goodbye to
}

}  // namespace
}  // namespace poet::worker
