#!/usr/bin/env bash
# Would more ES a step, or a wider search, have solved the third deep run's frontier? From the best θ of its one admitted challenging
# pair (28: roughness 0.8, gaps 0–0.8, stumps 0.2–2.4; retired unsolved at iteration 400, best evaluation 183.3;
# experiments/deep/frontier-es/pair-28.best.json), 40 ES steps on its own course and terrain seed, ES alone, for each
# setting of experiments/deep/frontier-es/<setting>-28.textproto:
#   A the deep preset's ES (64 rollouts a step, σ 0.05, lr 0.01)   B four times the population (256 rollouts a step)
#   C σ 0.1 (the paper's)   D σ 0.2
# Prints per setting the best evaluation, the mean of the first and last ten, the evaluations that finished the
# course and those that reached the solved score (230), and the environment steps spent.
# Usage: bash experiments/frontier_es.sh BUILD_DIR OUT_DIR [SETTING ...]   (default A B; all at once, one thread each)
set -euo pipefail
usage="usage: bash experiments/frontier_es.sh BUILD_DIR OUT_DIR [SETTING ...]"
build=${1:?$usage}
out=${2:?$usage}
shift 2
settings=("$@")
[[ $# -gt 0 ]] || settings=(A B)
root=$(cd "$(dirname "$0")/.." && pwd)
dir=$root/experiments/deep/frontier-es
coordinator=$build/coordinator/poet-coordinator
[[ -x $coordinator ]] || { echo "no $coordinator: build first" >&2; exit 2; }
mkdir -p "$out"
for setting in "${settings[@]}"; do
  [[ -f $dir/$setting-28.textproto ]] || { echo "no setting $setting: $dir/$setting-28.textproto" >&2; exit 2; }
done
for setting in "${settings[@]}"; do
  "$coordinator" --config "$dir/$setting-28.textproto" --run-dir "$out/$setting-28" \
    --start-from "$dir/pair-28.best.json" --threads 1 --quiet --status-address "" >>"$out/$setting-28.log" 2>&1 &
done
wait
for setting in "${settings[@]}"; do
  awk -F, -v s="$setting" 'NR > 1 {
      n++; if (n == 1 || $4 > best) best = $4; if ($5 == "true") finished++; if ($4 >= 230) solved++
      if (n <= 10) first += $4; if (n > 30) last += $4; steps = $17 }
    END { printf "setting %s: %d ES steps, best evaluation %.1f, mean of the first ten %.1f, of the last ten %.1f, %d finished, %d at 230 or more, %.1f M environment steps\n",
          s, n, best, first / 10, last / 10, finished, solved, steps / 1e6 }' "$out/$setting-28/pair_stats.csv"
done
