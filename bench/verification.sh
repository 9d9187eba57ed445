#!/usr/bin/env bash
# What verification costs: the same run with two workers over --listen at several --verify-fraction values, its
# wall time, the answers checked (by a second worker or the coordinator itself), and whether the checkpoint is the
# same as without checks.
# Usage: bash bench/verification.sh BUILD_DIR [CONFIG] [ITERATIONS] [FRACTIONS...]
#   defaults: deploy/configs/small.textproto, 3 iterations, fractions 0 0.05 0.25 1
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:?usage: bash bench/verification.sh BUILD_DIR [CONFIG] [ITERATIONS] [FRACTIONS...]}
config=${2:-$root/deploy/configs/small.textproto}
iterations=${3:-3}
shift $(($# < 3 ? $# : 3))
fractions=("$@")
((${#fractions[@]})) || fractions=(0 0.05 0.25 1)
coordinator=$build/coordinator/poet-coordinator
worker=$build/worker/poet-worker
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')

echo "config $config, $iterations iterations, 2 workers of 1 thread each on loopback; load before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "| --verify-fraction | wall s | answers checked | by the coordinator | same checkpoint as 0 |"
echo "|---|---|---|---|---|"
for fraction in "${fractions[@]}"; do
  dir=$work/run-$fraction
  start=$(date +%s.%N)
  "$coordinator" --config "$config" --run-dir "$dir" --iterations "$iterations" --quiet --status-address "" \
    --listen "tcp://127.0.0.1:$port" --verify-fraction "$fraction" > /dev/null 2> "$work/log-$fraction" &
  pid=$!
  for name in a b; do "$worker" --connect "tcp://127.0.0.1:$port" --threads 1 --log-level warn 2>/dev/null & done
  wait "$pid"
  end=$(date +%s.%N)
  wait
  summary=$(grep -o 'verification: [0-9]* answers checked ([0-9]* by the coordinator' "$work/log-$fraction" | tail -1 || true)
  checked=$(sed -n 's/.*verification: \([0-9]*\) answers checked.*/\1/p' <<< "$summary")
  by_coordinator=$(sed -n 's/.*(\([0-9]*\) by the coordinator/\1/p' <<< "$summary")
  same="(the reference)"
  [[ $fraction != "${fractions[0]}" ]] && { cmp -s "$work/run-${fractions[0]}/checkpoint.pb" "$dir/checkpoint.pb" && same=yes || same=NO; }
  printf '| %s | %.1f | %s | %s | %s |\n' "$fraction" "$(echo "$end - $start" | bc)" "${checked:-0}" "${by_coordinator:-0}" "$same"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
