#!/usr/bin/env bash
# What a liar can do to a run: the same run with two honest workers and one liar over --listen, for each shape of
# liar, several times; whether it was caught, after how many wrong answers, how many times the run went back to a
# checkpoint, its wall time against the undisturbed run, and whether the checkpoint is the undisturbed run's.
# Usage: bash bench/liars.sh BUILD_DIR [CONFIG] [ITERATIONS] [TRIALS] [FRACTION]
#   defaults: deploy/configs/small.textproto, 5 iterations, 5 trials, --verify-fraction 0.05 (the --listen default)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:?usage: bash bench/liars.sh BUILD_DIR [CONFIG] [ITERATIONS] [TRIALS] [FRACTION]}
config=${2:-$root/deploy/configs/small.textproto}
iterations=${3:-5}
trials=${4:-5}
fraction=${5:-0.05}
coordinator=$build/coordinator/poet-coordinator
worker=$build/worker/poet-worker
# the liar: the tests' poet-test-worker (poet-worker with a fault), built with the tests (POET_BUILD_TESTS)
liar=$build/tests/support/test_worker/poet-test-worker
[[ -x $liar ]] || { echo "liars.sh: no $liar (build the target poet-test-worker)" >&2; exit 2; }
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')

# name | the liar's flags
shapes=(
  "every job|"
  "every job after 8 honest ones|--lie-after 8"
  "a tenth of its jobs after 8 honest ones|--lie-after 8 --lie-fraction 0.1"
  "where a public rule predicts no check, after 8 honest ones|--lie-after 8 --lie-where-predicted-unchecked"
)

# run DIR LOG [LIAR_FLAGS...]: the config with two honest workers (and a liar when flags are given); prints seconds
run() {
  local dir=$1 log=$2 with_liar=$3
  shift 3
  local start end pid
  start=$(date +%s.%N)
  "$coordinator" --config "$config" --run-dir "$dir" --iterations "$iterations" --quiet --status-address "" \
    --listen "tcp://127.0.0.1:$port" --verify-fraction "$fraction" > /dev/null 2> "$log" &
  pid=$!
  for name in honest-a honest-b; do "$worker" --connect "tcp://127.0.0.1:$port" --threads 1 --log-level warn 2>/dev/null & done
  if [[ $with_liar == yes ]]; then
    "$liar" --connect "tcp://127.0.0.1:$port" --threads 1 --fault wrong-results --name the-liar "$@" 2> "$log.liar" &
  fi
  wait "$pid"
  end=$(date +%s.%N)
  wait || true
  echo "$end - $start" | bc
}

echo "config $config, $iterations iterations, --verify-fraction $fraction, 2 honest workers and a liar of 1 thread each"
echo "on loopback, $trials runs a shape; load before: $(cut -d' ' -f1-3 /proc/loadavg)"
reference_seconds=$(run "$work/reference" "$work/reference.log" no)
printf 'undisturbed: %.1f s\n\n' "$reference_seconds"
echo "| liar | caught | wrong answers before caught (each run) | wrong answers that stand, not caught | went back | wall s (mean) | same checkpoint when caught |"
echo "|---|---|---|---|---|---|---|"
for shape in "${shapes[@]}"; do
  name=${shape%%|*}
  read -r -a flags <<< "${shape#*|}"
  caught=0 same=0 back=0 seconds=0 before=() standing=()
  for ((t = 0; t < trials; t++)); do
    dir=$work/run-$t
    rm -rf "$dir"
    s=$(run "$dir" "$work/log" yes "${flags[@]}")
    seconds=$(echo "$seconds + $s" | bc)
    lies=$(grep -c 'a wrong answer to job' "$work/log.liar" || true)
    if grep -q 'worker the-liar returned results' "$work/log"; then
      caught=$((caught + 1))
      before+=("$lies")
      cmp -s "$work/reference/checkpoint.pb" "$dir/checkpoint.pb" && same=$((same + 1))
    else
      standing+=("$lies")
    fi
    n=$(sed -n 's/.* \([0-9]*\) time(s) gone back to a checkpoint.*/\1/p' "$work/log" | tail -1)
    back=$((back + ${n:-0}))
  done
  printf '| %s | %d of %d | %s | %s | %d | %.1f | %d of %d |\n' "$name" "$caught" "$trials" "${before[*]:--}" \
    "${standing[*]:--}" "$back" "$(echo "$seconds / $trials" | bc -l)" "$same" "$caught"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
