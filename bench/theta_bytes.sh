#!/usr/bin/env bash
# The bytes a coordinator sends for θ, measured against the arithmetic: every worker that runs tasks of an ES step
# receives that step's θ once per batch (2,804 doubles: a 22,449-byte Job.thetas field). One ES-alone workload
# (ES steps of a fixed size from the shipped walker on the flat course) runs twice, on K1 and on K2 workers that
# connect through tests/support/delay_relay.py with no delay, which counts the bytes each way. Each ES step goes
# out cut into at least one job a worker, so every worker takes part, and the evaluation of each step's new θ is one
# task on one worker: the arithmetic predicts STEPS × (K + 1) θ copies in a run on K workers, and that the second run
# sends STEPS × (K2 − K1) θ copies more than the first, the rest (tasks, heartbeats) about the same. Both runs must
# end in the same checkpoint, which the script checks. Prints the prediction beside the measurement.
#   bash bench/theta_bytes.sh BUILD_DIR [STEPS] [PERTURBATIONS] [K1] [K2]     defaults: 10 steps, 32, 2 and 8
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

usage_error() {
  echo "theta_bytes.sh: $*" >&2
  echo "usage: bash bench/theta_bytes.sh BUILD_DIR [STEPS] [PERTURBATIONS] [K1] [K2]" >&2
  exit 2
}
[ $# -ge 1 ] && [ $# -le 5 ] || usage_error "expected BUILD_DIR and at most STEPS, PERTURBATIONS, K1 and K2"
build=$(cd "$1" 2>/dev/null && pwd) || usage_error "$1 is not a directory"
steps=${2:-10}
perturbations=${3:-32}
k1=${4:-2}
k2=${5:-8}
for v in "$steps" "$perturbations" "$k1" "$k2"; do
  [[ $v =~ ^[1-9][0-9]*$ ]] || usage_error "STEPS, PERTURBATIONS, K1 and K2 must be positive integers, got $v"
done
((k1 < k2)) || usage_error "K1 must be less than K2"
((2 * perturbations >= k2)) || usage_error "an ES step must have at least one task for each of the K2 workers"
coordinator=$build/coordinator/poet-coordinator
worker=$build/worker/poet-worker
[ -x "$coordinator" ] && [ -x "$worker" ] || usage_error "$build has no poet-coordinator and poet-worker (build first)"

source "$root/bench/es_workload.sh"
make_scratch theta-bytes  # pids: everything this script started and has not reaped

write_es_config "$scratch/es.textproto" "$steps" "$perturbations"

# run K: the workload on K one-thread workers through the relay; appends "K DIR DOWN UP" to runs
run() {
  local k=$1 dir=$scratch/run-$1 port relay_pid endpoint
  port=$(free_port)
  "$coordinator" --config "$scratch/es.textproto" --start-from "$root/data/walkers/flat-walker.json" --quiet \
    --status-address "" --run-dir "$dir" --listen "tcp://127.0.0.1:$port" --verify-fraction 0 >"$dir.log" 2>&1 &
  local coordinator_pid=$!
  pids=("$coordinator_pid")
  python3 "$root/tests/support/delay_relay.py" --listen 127.0.0.1:0 --target "127.0.0.1:$port" --rtt-ms 0 >"$dir.relay" 2>&1 &
  relay_pid=$!
  pids+=("$relay_pid")
  for _ in $(seq 100); do grep -q '^listening' "$dir.relay" && break; sleep 0.1; done
  endpoint=tcp://$(sed -n 's/^listening //p' "$dir.relay")
  [ "$endpoint" != tcp:// ] || { echo "theta_bytes.sh: the relay did not start:" >&2; cat "$dir.relay" >&2; exit 1; }
  local workers=()
  for ((w = 0; w < k; w++)); do
    "$worker" --connect "$endpoint" --threads 1 >>"$dir.workers.log" 2>&1 &
    workers+=($!)
    pids+=($!)
  done
  wait "$coordinator_pid" || { echo "theta_bytes.sh: the coordinator failed, see its log:" >&2; tail -5 "$dir.log" >&2; exit 1; }
  for pid in "${workers[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${workers[@]}"; do wait "$pid" 2>/dev/null || true; done
  kill -TERM "$relay_pid" 2>/dev/null || true
  wait "$relay_pid" 2>/dev/null || true
  pids=()
  read -r down up < <(sed -n 's/^relayed [0-9]* connections, \([0-9]*\) bytes to the target, \([0-9]*\) bytes from it$/\2 \1/p' "$dir.relay")
  [ -n "${down:-}" ] || { echo "theta_bytes.sh: the relay did not report its bytes:" >&2; cat "$dir.relay" >&2; exit 1; }
  echo "$k $dir $down $up" >>"$scratch/runs"
}

load_before=$(cut -d' ' -f1-3 /proc/loadavg)
run "$k1"
run "$k2"
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

python3 - "$scratch/runs" "$steps" "$perturbations" "$load_before" "$load_after" <<'EOF'
import csv, hashlib, sys

runs_file, steps, perturbations, before, after = sys.argv[1:]
steps, perturbations = int(steps), int(perturbations)
# a Job.thetas field: tag and length (1 + 3 bytes) around a Theta: hash (1 + 8) and packed values (1 + 3 + 2,804 × 8)
theta_field = 4 + 9 + 4 + 2804 * 8
rows = []
for line in open(runs_file):
    k, path, down, up = line.split()
    stats = list(csv.DictReader(open(f"{path}/pair_stats.csv")))
    rollouts = int(stats[-1]["run_rollouts"])
    digest = hashlib.sha256(open(f"{path}/checkpoint.pb", "rb").read()).hexdigest()
    rows.append((int(k), int(down), int(up), rollouts, digest))
if len({r[4] for r in rows}) != 1:
    sys.exit("theta_bytes.sh: the runs ended in different checkpoints")
(ka, da, ua, rollouts, digest), (kb, db, ub, _, _) = rows
predicted = steps * (kb - ka) * theta_field
measured = db - da
print(f"ES alone on the flat course from the shipped walker: {steps} ES steps of {2 * perturbations} rollouts, "
      f"{rollouts:,} rollouts in all, both runs ending in one checkpoint ({digest[:12]}); load average "
      f"(1, 5, 15 min) {before} before, {after} after")
print()
print("| workers | bytes to the workers | θ copies predicted (bytes) | the rest, per rollout "
      "| bytes from the workers, per rollout |")
print("|---|---|---|---|---|")
for k, down, up, _, _ in rows:
    copies = steps * (k + 1)  # every worker takes each step's θ; each evaluation's θ goes to one worker
    print(f"| {k} | {down:,} | {copies} ({copies * theta_field:,}) | {(down - copies * theta_field) / rollouts:,.0f} "
          f"| {up / rollouts:,.0f} |")
print()
print(f"{kb} workers against {ka}: {measured:,} bytes more measured, {predicted:,} predicted "
      f"({steps} steps × {kb - ka} workers × {theta_field:,} bytes); measured / predicted = {measured / predicted:.3f}")
EOF
