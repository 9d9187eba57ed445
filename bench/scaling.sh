#!/usr/bin/env bash
# One fixed POET workload on 1, 2, ..., N rollout threads of the coordinator, then on 1, 2, ..., N poet-worker
# processes of one thread each on this machine: wall time, rollouts per second, speedup and parallel efficiency
# against one thread, the serial fraction the speedup implies (Karp-Flatt: (1/S - 1/k) / (1 - 1/k)) and the one the
# coordinator measured (its own work: the share of the wall time it did not spend waiting for rollouts,
# wall_times.csv's waiting_s). Every run must end in the same checkpoint (the run is a function of its config and
# seed), which the script checks. Prints a Markdown table.
#   bash bench/scaling.sh BUILD_DIR [N] [ITERATIONS]     N: default the machine's cores; ITERATIONS: default 12
# The workload is the quick preset (deploy/configs/quick.textproto) from the shipped walker for ITERATIONS
# iterations. Workers are started here with --threads 1 and trusted (--verify-fraction 0: they are this machine's
# own processes). On a larger machine: bash bench/scaling.sh build 16 30
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

usage_error() {
  echo "scaling.sh: $*" >&2
  echo "usage: bash bench/scaling.sh BUILD_DIR [N] [ITERATIONS]" >&2
  exit 2
}
[ $# -ge 1 ] && [ $# -le 3 ] || usage_error "expected BUILD_DIR and at most N and ITERATIONS"
build=$(cd "$1" 2>/dev/null && pwd) || usage_error "$1 is not a directory"
max=${2:-$(nproc)}
iterations=${3:-12}
[[ $max =~ ^[1-9][0-9]*$ ]] || usage_error "N must be a positive integer, got $max"
[[ $iterations =~ ^[1-9][0-9]*$ ]] || usage_error "ITERATIONS must be a positive integer, got $iterations"
coordinator=$build/coordinator/poet-coordinator
worker=$build/worker/poet-worker
[ -x "$coordinator" ] && [ -x "$worker" ] || usage_error "$build has no poet-coordinator and poet-worker (build first)"

scratch=$(mktemp -d /tmp/poet-scaling.XXXXXX)
workers=()
cleanup() {
  for pid in "${workers[@]}"; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$scratch"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

common=(--config "$root/deploy/configs/quick.textproto" --start-from "$root/data/walkers/flat-walker.json"
  --iterations "$iterations" --quiet --status-address "")

free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

# run NAME COUNT: the workload on COUNT threads (NAME threads) or COUNT one-thread workers (NAME workers)
run() {
  local kind=$1 count=$2 dir=$scratch/$1-$2
  if [ "$kind" = threads ]; then
    "$coordinator" "${common[@]}" --run-dir "$dir" --threads "$count" >"$dir.log" 2>&1
  else
    local port
    port=$(free_port)
    "$coordinator" "${common[@]}" --run-dir "$dir" --listen "tcp://127.0.0.1:$port" --verify-fraction 0 \
      >"$dir.log" 2>&1 &
    local coordinator_pid=$!
    workers=()
    for ((w = 0; w < count; w++)); do
      "$worker" --connect "tcp://127.0.0.1:$port" --threads 1 >>"$dir.workers.log" 2>&1 &
      workers+=($!)
    done
    wait "$coordinator_pid" || { echo "scaling.sh: the coordinator failed, see $dir.log:" >&2; tail -5 "$dir.log" >&2; exit 1; }
    for pid in "${workers[@]}"; do kill "$pid" 2>/dev/null || true; done
    for pid in "${workers[@]}"; do wait "$pid" 2>/dev/null || true; done
    workers=()
  fi
  echo "$kind $count $dir" >>"$scratch/runs"
}

for ((k = 1; k <= max; k++)); do run threads "$k"; done
for ((k = 1; k <= max; k++)); do run workers "$k"; done

python3 - "$scratch/runs" "$iterations" "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)" <<'EOF'
import csv, hashlib, sys

runs_file, iterations, cores, load = sys.argv[1:]
rows = []
for line in open(runs_file):
    kind, count, path = line.split()
    walls = list(csv.DictReader(open(f"{path}/wall_times.csv")))
    wall = float(walls[-1]["wall_s"])
    waiting = sum(float(w["waiting_s"]) for w in walls)
    stats = list(csv.DictReader(open(f"{path}/pair_stats.csv")))
    rollouts = int(stats[-1]["run_rollouts"])
    digest = hashlib.sha256(open(f"{path}/checkpoint.pb", "rb").read()).hexdigest()
    rows.append((kind, int(count), wall, waiting, rollouts, digest))

if len({r[5] for r in rows}) != 1:
    sys.exit("scaling.sh: the runs ended in different checkpoints: " + ", ".join(f"{r[0]} {r[1]}: {r[5][:12]}" for r in rows))
print(f"{iterations} iterations of the quick preset from the shipped walker, {rows[0][4]:,} rollouts each run, "
      f"all ending in one checkpoint ({rows[0][5][:12]}); {cores} cores, load average over the last minute {load.split()[0]} (the runs' own)")
print()
print("| rollouts on | wall time | rollouts/s | speedup | parallel efficiency | serial fraction (Karp-Flatt) "
      "| coordinator's own work (measured) |")
print("|---|---|---|---|---|---|---|")
for kind in ("threads", "workers"):
    base = next((r for r in rows if r[0] == kind and r[1] == 1), None)
    for r in (r for r in rows if r[0] == kind):
        speedup = base[2] / r[2]
        k = r[1]
        karp_flatt = "-" if k == 1 else f"{(1 / speedup - 1 / k) / (1 - 1 / k):.3f}"
        label = f"{k} thread{'s' if k > 1 else ''}" if kind == "threads" else f"{k} worker{'s' if k > 1 else ''} of 1 thread"
        print(f"| {label} | {r[2]:.1f} s | {r[4] / r[2]:,.0f} | {speedup:.2f} | {speedup / k:.2f} | {karp_flatt} "
              f"| {1 - r[3] / r[2]:.3f} |")
EOF
