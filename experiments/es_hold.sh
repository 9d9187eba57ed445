#!/usr/bin/env bash
# Can ES hold a walker that crossed a course at the frontier? From the best θ of pairs 37 and 40 of the deep preset's
# first run (experiments/deep/es-hold/pair-*.best.json: each crossed its own course once, scoring 260.9 and 249.7),
# 25 ES steps on that pair's course (ES alone, the run's course and terrain seed) for each ES setting of
# experiments/deep/es-hold/<setting>-<pair>.textproto:
#   A σ 0.05, 64 rollouts, lr 0.01 (the preset's)   B σ 0.02   C 128 rollouts   D lr 0.005   E σ 0.02, 128 rollouts
#   F σ 0.03
# Prints per run the mean evaluation over the 25 steps, over the first and last five, how many evaluations reached
# 200 and how many solved the course (finished, ≥ 230), and the mean perturbation return.
# Usage: bash experiments/es_hold.sh BUILD_DIR OUT_DIR   (runs two at a time, one thread each)
set -euo pipefail
usage="usage: bash experiments/es_hold.sh BUILD_DIR OUT_DIR"
build=${1:?$usage}
out=${2:?$usage}
root=$(cd "$(dirname "$0")/.." && pwd)
dir=$root/experiments/deep/es-hold
coordinator=$build/coordinator/poet-coordinator
[[ -x $coordinator ]] || { echo "no $coordinator: build first" >&2; exit 2; }
mkdir -p "$out"
run() {  # SETTING PAIR
  "$coordinator" --config "$dir/$1-$2.textproto" --run-dir "$out/$1-$2" --start-from "$dir/pair-$2.best.json" \
    --threads 1 --quiet --status-address "" >>"$out/$1-$2.log" 2>&1
}
for setting in A B C D E F; do
  run "$setting" 37 &
  run "$setting" 40
  wait
done
for pair in 37 40; do
  for setting in A B C D E F; do
    awk -F, -v s="$setting" -v p="$pair" 'NR > 1 {
        n++; sum += $4; if ($4 >= 200) reached++; if ($5 == "true" && $4 >= 230) solved++; pert += $12
        if (n <= 5) first += $4; if (n > 20) last += $4 }
      END { printf "pair %s, setting %s: mean evaluation %.1f (first five %.1f, last five %.1f), %d of %d at 200 or more, %d solved, mean perturbation return %.1f\n",
            p, s, sum / n, first / 5, last / 5, reached, n, solved, pert / n }' "$out/$setting-$pair/pair_stats.csv"
  done
done
