#!/usr/bin/env bash
# Resident memory of poet-coordinator and of its local workers over a run on 2 local workers: VmRSS and VmHWM
# from /proc once a second, one line per iteration (the iteration and the pairs from the status socket), then a
# summary: the coordinator's RSS at the first iteration and the last, its growth per iteration, the workers' peak.
# Usage: bash bench/memory_bench.sh BUILD_DIR [ITERATIONS] [CONFIG]
#   defaults: 20 iterations of deploy/configs/quick.textproto (about two minutes on an idle 2-core machine)
set -euo pipefail
usage="usage: bash bench/memory_bench.sh BUILD_DIR [ITERATIONS] [CONFIG]"
build=${1:?$usage}
iterations=${2:-20}
root=$(cd "$(dirname "$0")/.." && pwd)
config=${3:-$root/deploy/configs/quick.textproto}
coordinator_bin=$build/coordinator/poet-coordinator
[[ -x $coordinator_bin ]] || { echo "no $coordinator_bin: build first" >&2; exit 2; }

work=$(mktemp -d /tmp/poet-memory-bench.XXXXXX)
coordinator=
declare -A workers_seen=()
cleanup() {
  # the coordinator stops its workers on SIGTERM; any worker it left behind (a KILLed coordinator) goes too
  if [[ -n $coordinator ]] && kill -0 "$coordinator" 2>/dev/null; then
    kill -TERM "$coordinator" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$coordinator" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$coordinator" 2>/dev/null || true
  fi
  for w in "${!workers_seen[@]}"; do kill -KILL "$w" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# a number field of the /status JSON in $body ("iteration": 12)
number() { grep -o "\"$1\": *[0-9]*" <<<"$body" | grep -o '[0-9]*$' || true; }
# kB of a /proc/PID/status field, 0 once the process is gone
field() {
  local kb
  kb=$(awk -v f="$2:" '$1 == f { print $2 }' "/proc/$1/status" 2>/dev/null) || true
  echo "${kb:-0}"
}

"$coordinator_bin" --config "$config" --run-dir "$work/run" --local-workers 2 \
  --iterations "$iterations" --status-address 127.0.0.1:0 --quiet >"$work/out" 2>"$work/log" &
coordinator=$!

# the status socket's port, from the log line "status: http://127.0.0.1:PORT/status"
address=
for _ in $(seq 100); do
  address=$(grep -o 'status: http://[0-9.:]*' "$work/log" | head -n 1 | sed 's|status: http://||') || true
  [[ -n $address ]] && break
  kill -0 "$coordinator" 2>/dev/null || { cat "$work/log" >&2; exit 1; }
  sleep 0.1
done
[[ -n $address ]] || { echo "no status address in the coordinator's log" >&2; exit 1; }

echo "iteration  pairs(created/active)  elapsed_s  coord_rss_kB  coord_hwm_kB  worker_rss_kB(each)  worker_hwm_kB(max)"
start=$(date +%s)
last_iteration=-1
worker_hwm_max=0
worker_rss_max=0
: >"$work/per_iteration"
while kill -0 "$coordinator" 2>/dev/null; do
  body=$(curl -s --max-time 1 "http://$address/status") || body=
  iteration=$(number iteration)
  pairs="$(number pairs_created)/$(number pairs_active)"
  rss=$(field "$coordinator" VmRSS)
  hwm=$(field "$coordinator" VmHWM)
  worker_rss=()
  for w in $(pgrep -P "$coordinator" || true); do
    workers_seen[$w]=1
    r=$(field "$w" VmRSS)
    h=$(field "$w" VmHWM)
    worker_rss+=("$r")
    ((r > worker_rss_max)) && worker_rss_max=$r
    ((h > worker_hwm_max)) && worker_hwm_max=$h
  done
  # one line per iteration: the first sample taken while the run is on it
  if [[ -n $iteration && $iteration != "$last_iteration" && $rss -gt 0 ]]; then
    printf '%9s  %21s  %9s  %12s  %12s  %19s  %18s\n' "$iteration" "$pairs" $(($(date +%s) - start)) "$rss" "$hwm" \
      "$(IFS=,; echo "${worker_rss[*]:-none}")" "$worker_hwm_max"
    echo "$iteration $rss" >>"$work/per_iteration"
    last_iteration=$iteration
  fi
  sleep 1
done
wait "$coordinator" && status=0 || status=$?
coordinator=
[[ $status -eq 0 ]] || { echo "poet-coordinator exited $status:" >&2; tail -n 20 "$work/log" >&2; exit 1; }

# growth per iteration: the least-squares slope of the coordinator's RSS over the iterations sampled, and over
# their second half alone (past the first batches, whose buffers and allocator arenas grow once)
awk -v wmax="$worker_rss_max" -v whwm="$worker_hwm_max" '
  function slope(from, to,   i, k, sx, sy, sxx, sxy) {
    for (i = from; i <= to; i++) { k++; sx += x[i]; sy += y[i]; sxx += x[i] * x[i]; sxy += x[i] * y[i] }
    return k < 2 ? 0 : (k * sxy - sx * sy) / (k * sxx - sx * sx)
  }
  { n++; x[n] = $1; y[n] = $2 }
  END {
    if (n < 4) { print "too few iterations sampled"; exit 1 }
    half = int(n / 2) + 1
    printf "summary: coordinator RSS %d kB at iteration %d, %d kB at iteration %d; growth %.1f kB/iteration " \
           "(least squares over %d iterations), %.1f kB/iteration from iteration %d on; worker RSS max %d kB " \
           "(VmHWM max %d kB)\n", y[1], x[1], y[n], x[n], slope(1, n), n, slope(half, n), x[half], wmax, whwm
  }' "$work/per_iteration"
