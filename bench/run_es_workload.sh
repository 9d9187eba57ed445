#!/usr/bin/env bash
# Runs the 2048-population, 50-step ES workload (bench/es_workload.textproto) with N threads (default 2) and
# prints its summary: wall time, rollouts and environment steps. Usage: bench/run_es_workload.sh [THREADS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
threads=${1:-2}
run_dir=$(mktemp -d /tmp/poet-es-workload.XXXXXX)
trap 'rm -rf "$run_dir"' EXIT
"$root/build/coordinator/poet-coordinator" --config "$root/bench/es_workload.textproto" --run-dir "$run_dir/run" \
  --threads "$threads" --quiet
tail -n 1 "$run_dir/run/pair_stats.csv" | cut -d, -f1-9
