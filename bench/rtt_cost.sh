#!/usr/bin/env bash
# What round-trip time costs a run: one fixed ES workload on W poet-worker processes that connect to the coordinator
# directly, then through tests/support/delay_relay.py at each given round-trip time (the kernel here has no netem;
# the relay delays each direction's bytes by RTT/2 and keeps their order). The workload is ES alone on the flat
# course from the shipped walker, in small ES steps (PERTURBATIONS mirrored pairs) so that round trips weigh against
# the episodes: each ES step is two batches, its rollouts and then the evaluation of the new θ. The whole sequence
# (direct, then each RTT) runs REPEATS times, interleaved, so that a change in the machine's load falls on every
# setting. For each setting: the wall times, their median, the slowdown against the direct runs' median, and the
# wall time added per batch, in milliseconds and in round trips. Every run must end in the same checkpoint, which the
# script checks. Prints a Markdown table.
#   bash bench/rtt_cost.sh BUILD_DIR [STEPS] [PERTURBATIONS] [REPEATS] [RTT_MS ...]
#   defaults: 30 ES steps of 8 mirrored pairs (16 rollouts), 3 repeats, RTT 0 25 50 100 ms
# Workers: W = 2 of one thread each (POET_RTT_WORKERS to change), trusted (--verify-fraction 0: this machine's own).
# POET_RTT_MAX_STEPS=N caps the episodes at N steps (the walker's max_steps, default 2,000): with short episodes the
# wall time is mostly round trips, and a busy machine's load hardly moves it.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

usage_error() {
  echo "rtt_cost.sh: $*" >&2
  echo "usage: bash bench/rtt_cost.sh BUILD_DIR [STEPS] [PERTURBATIONS] [REPEATS] [RTT_MS ...]" >&2
  exit 2
}
[ $# -ge 1 ] || usage_error "expected BUILD_DIR"
build=$(cd "$1" 2>/dev/null && pwd) || usage_error "$1 is not a directory"
steps=${2:-30}
perturbations=${3:-8}
repeats=${4:-3}
shift $(($# >= 4 ? 4 : $#))
rtts=("$@")
[ ${#rtts[@]} -gt 0 ] || rtts=(0 25 50 100)
workers_count=${POET_RTT_WORKERS:-2}
max_steps=${POET_RTT_MAX_STEPS:-2000}
for v in "$steps" "$perturbations" "$repeats" "$workers_count" "$max_steps"; do
  [[ $v =~ ^[1-9][0-9]*$ ]] ||
    usage_error "STEPS, PERTURBATIONS, REPEATS, POET_RTT_WORKERS and POET_RTT_MAX_STEPS must be positive integers, got $v"
done
for r in "${rtts[@]}"; do [[ $r =~ ^[0-9]+$ ]] || usage_error "each RTT_MS must be a whole number, got $r"; done
coordinator=$build/coordinator/poet-coordinator
worker=$build/worker/poet-worker
[ -x "$coordinator" ] && [ -x "$worker" ] || usage_error "$build has no poet-coordinator and poet-worker (build first)"

source "$root/bench/es_workload.sh"
make_scratch rtt  # pids: everything this script started and has not reaped

write_es_config "$scratch/es.textproto" "$steps" "$perturbations" "$max_steps"

# run NAME RTT: the workload with the workers connected directly (RTT "-") or through the relay at RTT ms
run() {
  local name=$1 rtt=$2 dir=$scratch/$1 port relay_pid= endpoint
  port=$(free_port)
  "$coordinator" --config "$scratch/es.textproto" --start-from "$root/data/walkers/flat-walker.json" --quiet \
    --status-address "" --run-dir "$dir" --listen "tcp://127.0.0.1:$port" --verify-fraction 0 >"$dir.log" 2>&1 &
  local coordinator_pid=$!
  pids=("$coordinator_pid")
  endpoint=tcp://127.0.0.1:$port
  if [ "$rtt" != - ]; then
    python3 "$root/tests/support/delay_relay.py" --listen 127.0.0.1:0 --target "127.0.0.1:$port" --rtt-ms "$rtt" \
      >"$dir.relay" 2>&1 &
    relay_pid=$!
    pids+=("$relay_pid")
    for _ in $(seq 100); do grep -q '^listening' "$dir.relay" && break; sleep 0.1; done
    endpoint=tcp://$(sed -n 's/^listening //p' "$dir.relay")
    [ "$endpoint" != tcp:// ] || { echo "rtt_cost.sh: the relay did not start:" >&2; cat "$dir.relay" >&2; exit 1; }
  fi
  for ((w = 0; w < workers_count; w++)); do
    "$worker" --connect "$endpoint" --threads 1 >>"$dir.workers.log" 2>&1 &
    pids+=($!)
  done
  wait "$coordinator_pid" || { echo "rtt_cost.sh: the coordinator failed, see its log:" >&2; tail -5 "$dir.log" >&2; exit 1; }
  # the workers, then the relay, which prints what it carried once it is stopped
  for pid in "${pids[@]:1}"; do [ "$pid" = "$relay_pid" ] || kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]:1}"; do [ "$pid" = "$relay_pid" ] || wait "$pid" 2>/dev/null || true; done
  if [ -n "$relay_pid" ]; then
    kill -TERM "$relay_pid" 2>/dev/null || true
    wait "$relay_pid" 2>/dev/null || true
  fi
  pids=()
  echo "$name $rtt $dir" >>"$scratch/runs"
}

load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for ((i = 1; i <= repeats; i++)); do
  run "direct-$i" -
  for r in "${rtts[@]}"; do run "relay-$r-$i" "$r"; done
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg)

python3 - "$scratch/runs" "$steps" "$perturbations" "$workers_count" "$max_steps" "$load_before" "$load_after" <<'EOF'
import csv, hashlib, re, statistics, sys

runs_file, steps, perturbations, workers, max_steps, before, after = sys.argv[1:]
batches = 2 * int(steps)  # each ES step: its rollouts, then the evaluation of the new θ
settings = {}  # rtt ("-" for direct) -> [(wall, down, up)]
digests, rollouts = set(), None
for line in open(runs_file):
    name, rtt, path = line.split()
    wall = float(list(csv.DictReader(open(f"{path}/wall_times.csv")))[-1]["wall_s"])
    rollouts = int(list(csv.DictReader(open(f"{path}/pair_stats.csv")))[-1]["run_rollouts"])
    digests.add(hashlib.sha256(open(f"{path}/checkpoint.pb", "rb").read()).hexdigest())
    down = up = None
    if rtt != "-":
        m = re.search(r"relayed \d+ connections, (\d+) bytes to the target, (\d+) bytes from it",
                      open(f"{path}.relay").read())
        up, down = (int(m.group(1)), int(m.group(2))) if m else (None, None)
    settings.setdefault(rtt, []).append((wall, down, up))

if len(digests) != 1:
    sys.exit("rtt_cost.sh: the runs ended in different checkpoints: " + ", ".join(d[:12] for d in sorted(digests)))
direct = statistics.median(w for w, _, _ in settings["-"])
relay0 = statistics.median(w for w, _, _ in settings["0"]) if "0" in settings else None
print(f"ES alone on the flat course from the shipped walker, {steps} ES steps of {2 * int(perturbations)} rollouts "
      f"({batches} batches, {rollouts:,} rollouts of at most {int(max_steps):,} steps) on {workers} workers of one "
      f"thread; every run ending in one checkpoint ({next(iter(digests))[:12]}); load average (1, 5, 15 min) {before} "
      f"before, {after} after")
print()
print("| workers connect | wall times | median | slowdown | added per batch | round trips per batch, against the relay "
      "at 0 ms | bytes to workers, from workers |")
print("|---|---|---|---|---|---|---|")
points = []  # (rtt in s, median wall) of the relay's settings
for rtt, runs in settings.items():
    walls = [w for w, _, _ in runs]
    median = statistics.median(walls)
    label = "directly" if rtt == "-" else f"through the relay, RTT {rtt} ms"
    if rtt != "-":
        points.append((float(rtt) / 1000, median))
    trips = "-" if rtt in ("-", "0") or relay0 is None else f"{(median - relay0) / batches / (float(rtt) / 1000):.2f}"
    down, up = runs[0][1], runs[0][2]
    carried = "-" if down is None else f"{down / 1e6:.2f} MB, {up / 1e6:.2f} MB"
    print(f"| {label} | {', '.join(f'{w:.1f}' for w in walls)} s | {median:.1f} s | {median / direct:.2f} "
          f"| {(median - direct) / batches * 1000:+.0f} ms | {trips} | {carried} |")
if len({x for x, _ in points}) >= 2:
    mx = sum(x for x, _ in points) / len(points)
    my = sum(y for _, y in points) / len(points)
    slope = sum((x - mx) * (y - my) for x, y in points) / sum((x - mx) ** 2 for x, _ in points)
    print()
    print(f"least squares over the relay's settings: {slope:.1f} s of wall time per second of round trip, "
          f"{slope / batches:.2f} round trips per batch; the relay itself (at 0 ms) adds "
          f"{((relay0 or direct) - direct) / batches * 1000:.0f} ms a batch")
EOF
