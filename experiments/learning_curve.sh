#!/usr/bin/env bash
# A learning curve: runs a config (ES alone, typically) and writes, per ES step, the evaluation score against ES
# steps, environment steps and wall time on this machine, then says when the course was solved (finished with a
# score of at least 230: spec §1.4's "solved").
# Usage: bash experiments/learning_curve.sh BUILD_DIR CONFIG ITERATIONS OUT_DIR [coordinator flags...]
#   e.g. bash experiments/learning_curve.sh build data/walkers/flat-walker.textproto 400 runs/curve-128 --threads 2
# OUT_DIR/run is the run directory, OUT_DIR/curve.csv the curve:
#   es_step,score,finished,env_steps,rollouts,wall_s
# Run it again with the same OUT_DIR (and a larger ITERATIONS, if the limit was reached) and it resumes the run
# from its checkpoint: the numbers stay those of an uninterrupted run and the clock continues from the last
# recorded step. Wall time is sampled twice a second from the moment a step's row appears in pair_stats.csv, so
# it is good to half a second; the time between an interruption and its last checkpoint is not counted.
set -euo pipefail
usage="usage: bash experiments/learning_curve.sh BUILD_DIR CONFIG ITERATIONS OUT_DIR [coordinator flags...]"
build=${1:?$usage}
config=${2:?$usage}
iterations=${3:?$usage}
out=${4:?$usage}
shift 4
coordinator_bin=$build/coordinator/poet-coordinator
[[ -x $coordinator_bin ]] || { echo "no $coordinator_bin: build first" >&2; exit 2; }
[[ -f $config ]] || { echo "no config $config" >&2; exit 2; }
mkdir -p "$out"
stats=$out/run/pair_stats.csv
times=$out/wall.csv

coordinator=
cleanup() {
  if [[ -n $coordinator ]] && kill -0 "$coordinator" 2>/dev/null; then
    kill -TERM "$coordinator" 2>/dev/null || true  # it checkpoints and leaves within a second
    wait "$coordinator" 2>/dev/null || true
  fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

if [[ -f $out/run/checkpoint.pb ]]; then
  [[ -f $times ]] || { echo "$out/run exists but $times does not: not a learning-curve directory" >&2; exit 2; }
  run_source=(--resume)
  # steps already timed keep their times (a step past the checkpoint is recomputed with the same numbers)
  seen=$(($(wc -l <"$times") - 1))
  elapsed=$(awk -F, 'NR > 1 { last = $2 } END { print (last == "" ? 0 : last) }' "$times")
else
  run_source=(--config "$config")
  echo "iteration,wall_s" >"$times"
  seen=0
  elapsed=0
fi
start=$(awk -v now="$(date +%s.%N)" -v e="$elapsed" 'BEGIN { printf "%.2f", now - e }')

"$coordinator_bin" "${run_source[@]}" --run-dir "$out/run" --iterations "$iterations" --quiet \
  --status-address "" "$@" >>"$out/coordinator.out" 2>>"$out/coordinator.log" &
coordinator=$!
record() {  # the wall time of every row that appeared since the last look
  [[ -f $stats ]] || return 0
  local rows now
  rows=$(($(wc -l <"$stats") - 1))
  now=$(date +%s.%N)
  while ((seen < rows)); do
    awk -v i="$seen" -v a="$now" -v b="$start" 'BEGIN { printf "%d,%.2f\n", i, a - b }' >>"$times"
    seen=$((seen + 1))
  done
}
while kill -0 "$coordinator" 2>/dev/null; do
  record
  sleep 0.5
done
status=0
wait "$coordinator" || status=$?
coordinator=
record
if ((status == 130 || status == 143)); then
  echo "poet-coordinator was interrupted ($status): the curve holds the steps of its last checkpoint" >&2
elif ((status != 0)); then
  echo "poet-coordinator exited $status:" >&2
  tail -n 5 "$out/coordinator.log" >&2
  exit "$status"
fi

# pair 0's rows (ES alone has one pair), joined with their wall times by iteration
awk -F, '
  NR == FNR { if (FNR > 1) wall[$1] = $2; next }
  FNR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; print "es_step,score,finished,env_steps,rollouts,wall_s"; next }
  $col["pair"] == 0 {
    print $col["es_steps"] "," $col["score"] "," $col["finished"] "," $col["run_env_steps"] "," $col["run_rollouts"] "," wall[$col["iteration"]]
  }' "$times" "$stats" >"$out/curve.csv"

awk -F, 'NR > 1 && $3 == "true" && $2 >= 230 {
    printf "solved at ES step %d: score %.1f, %d environment steps, %d rollouts, %.0f s\n", $1, $2, $4, $5, $6; found = 1; exit }
  END { if (!found) print "not solved within the run" }' "$out/curve.csv"
tail -n 1 "$out/curve.csv" | awk -F, '{ printf "last: ES step %d, score %.1f, %d environment steps, %.0f s\n", $1, $2, $4, $6 }'
echo "curve: $out/curve.csv"
