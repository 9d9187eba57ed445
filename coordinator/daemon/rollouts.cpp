#include "coordinator/daemon/rollouts.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>
#include <utility>

#include "common/plumbing/curve_keys.h"
#include "common/plumbing/local_token.h"
#include "common/program/build_fingerprint.h"
#include "coordinator/evaluator/local_evaluator.h"
#include "run_directory/files/run_directory.h"

namespace poet {
namespace {

// Workers that connect to --listen without CURVE may be anyone's: this fraction of their jobs is checked by a
// second worker unless --verify-fraction says otherwise (the cost is about this fraction of the rollouts).
constexpr double kListenVerifyFraction = 0.05;

// The job socket's CURVE keys from DIR (common/plumbing/curve_keys.h), checked before anything listens; local workers
// use DIR's worker key, so it must be there and authorised too.
std::optional<CurveServer> curve_server(const std::filesystem::path& dir, bool local_workers, std::string& public_key) {
  Expected<CurveKeyPair> keys = read_key_pair(dir, "coordinator");
  // a file of authorized/ that holds no key is skipped, here as at every handshake (curve_authenticator.h)
  Expected<AuthorizedKeys> authorized = scan_authorized_keys(dir);
  if (!keys || !authorized) {
    spdlog::error("--curve-keys: {} (make keys with `poetctl keygen`)", keys ? authorized.error() : keys.error());
    return std::nullopt;
  }
  const std::vector<std::string>& authorized_keys = authorized->keys;
  if (local_workers) {
    Expected<CurveKeyPair> worker = read_key_pair(dir, "worker");
    if (!worker || !std::binary_search(authorized_keys.begin(), authorized_keys.end(), worker->public_key)) {
      spdlog::error("--curve-keys with --local-workers: {}",
                    worker ? "worker.key is not in authorized/" : worker.error());
      return std::nullopt;
    }
  }
  if (authorized_keys.empty())
    spdlog::warn("--curve-keys: no key in {}: no worker can connect until one is added", (dir / "authorized").string());
  spdlog::info("CURVE on: workers need one of the {} keys in {}", authorized_keys.size(),
               (dir / "authorized").string());
  public_key = keys->public_key;
  return CurveServer{keys->secret_key, dir, {}, {}};  // the callbacks and files: set by the caller
}

// A run that was finished when opened: the workers an orchestrator starts beside it (Compose starts them once
// /healthz answers) would try to reach a coordinator for ever; for --linger seconds each one that connects is told
// the run is finished and exits 0. A stop request ends the wait.
void linger(const DaemonOptions& options, StopSignals& signals) {
  spdlog::info("the run was finished already; workers that connect in the next {} s are told so, then this exits",
               options.linger_seconds);
  std::mutex mutex;
  std::condition_variable_any stopped;
  std::unique_lock lock(mutex);
  stopped.wait_for(lock, signals.token(), std::chrono::seconds(options.linger_seconds), [] { return false; });
}

}  // namespace

std::optional<Rollouts> make_rollouts(const DaemonOptions& options, StopSignals& signals, StatusBoard& board) {
  Rollouts r;
  if (options.listen.empty() && options.local_workers == 0) {
    r.evaluator = std::make_unique<LocalEvaluator>(options.threads, signals.token());
    return r;
  }
  DispatchSettings settings;
  settings.liveness_ms = options.liveness_ms;
  settings.heartbeat_ms = wire_timing::heartbeat_ms(options.liveness_ms);
  settings.build = {build_fingerprint_digest(), arithmetic_digest(), arithmetic_text()};
  settings.local_token = make_local_token();
  settings.verify_fraction = options.verify_fraction.value_or(
      !options.listen.empty() && options.curve_keys.empty() ? kListenVerifyFraction : 0.0);
  settings.verify_secret = make_verify_secret();
  if (settings.verify_fraction > 0)
    spdlog::info("verification: {:g} of the jobs of workers not started here also run on a second worker",
                 settings.verify_fraction);
  const std::string endpoint = options.listen.empty() ? "tcp://127.0.0.1:*" : options.listen;
  std::optional<CurveServer> curve;
  std::vector<std::string> worker_args;  // for every local worker
  if (!options.curve_keys.empty()) {
    curve = curve_server(options.curve_keys, options.local_workers > 0, r.curve_public_key);
    if (!curve) return std::nullopt;
    curve->skipped_key_file = [&board] { board.count_skipped_key_file(); };
    curve->refused_keys_file = std::filesystem::path(options.run_dir) / kRefusedKeysFile;
    worker_args.insert(worker_args.begin(), {"--curve-keys", options.curve_keys});
  }
  Expected<std::unique_ptr<RemoteEvaluator>> remote =
      RemoteEvaluator::bind(endpoint, settings, signals.token(), std::move(curve));
  if (!remote) {
    spdlog::error("{}", remote.error());
    return std::nullopt;
  }
  r.remote = remote->get();
  r.evaluator = std::move(*remote);
  r.worker_args = std::move(worker_args);
  r.local_token = settings.local_token;
  spdlog::info("workers connect to {}", r.remote->endpoint());
  return r;
}

bool start_local_workers(const DaemonOptions& options, Rollouts& r) {
  if (options.local_workers == 0) return true;
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = std::max(1, hardware / options.local_workers);
  const std::string binary = options.worker_binary.empty() ? LocalWorkers::default_binary() : options.worker_binary;
  Expected<std::unique_ptr<LocalWorkers>> workers =
      LocalWorkers::start(binary, r.remote->endpoint(), options.local_workers, threads, r.local_token, r.worker_args);
  if (!workers) {
    spdlog::error("{}", workers.error());
    return false;
  }
  r.local_workers = std::move(*workers);
  spdlog::info("started {} local workers ({}) with {} threads each", options.local_workers, binary, threads);
  return true;
}

void end_rollouts(const DaemonOptions& options, StopSignals& signals, StatusBoard& board, Rollouts& r, bool finished,
                  bool finished_when_opened) {
  if (r.remote) r.remote->log_summary();
  if (!finished) return;
  if (r.remote) r.remote->on_snapshot(nullptr);  // first, so that no snapshot of the dispatcher says "running" again
  board.set_state(RunPhase::kFinished);
  if (!r.remote) return;
  r.remote->shutdown_workers("the run is finished");
  if (finished_when_opened && options.linger_seconds > 0) linger(options, signals);
}

}  // namespace poet
