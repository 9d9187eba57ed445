#!/usr/bin/env bash
# What an ES run's perturbations did, window by window: for one pair of a run directory, per WINDOW ES steps, the
# mean evaluation score, the mean and the best of the perturbations' returns (pair_stats.csv's perturbation_mean
# and perturbation_max), how many steps had a perturbation above THRESHOLD, and σ and ‖θ‖ at the window's end.
# It tells a run that stands still (no perturbation scores much above 0) from one whose perturbations already move.
# Usage: bash experiments/es_windows.sh RUN_DIR [PAIR=0] [WINDOW=50] [THRESHOLD=10]   (a Markdown table on stdout)
set -euo pipefail
usage="usage: bash experiments/es_windows.sh RUN_DIR [PAIR=0] [WINDOW=50] [THRESHOLD=10]"
run=${1:?$usage}
pair=${2:-0}
window=${3:-50}
threshold=${4:-10}
stats=$run/pair_stats.csv
[[ -f $stats ]] || { echo "no $stats: not a run directory" >&2; exit 2; }
[[ $pair =~ ^[0-9]+$ && $window =~ ^[1-9][0-9]*$ ]] || { echo "$usage" >&2; exit 2; }
[[ $threshold =~ ^-?[0-9]+([.][0-9]+)?$ ]] || { echo "THRESHOLD: not a number: $threshold" >&2; exit 2; }

awk -F, -v pair="$pair" -v window="$window" -v threshold="$threshold" -v file="$stats" '
  FNR == 1 {
    for (i = 1; i <= NF; i++) col[$i] = i
    split("pair es_steps score perturbation_mean perturbation_max sigma theta_norm", need, " ")
    for (k in need) if (!(need[k] in col)) { printf "%s: no column %s\n", file, need[k] > "/dev/stderr"; bad = 1; exit 2 }
    next
  }
  $col["pair"] == pair {
    w = int(($col["es_steps"] - 1) / window)
    if (!(w in n)) { order[++windows] = w; first[w] = $col["es_steps"]; best[w] = $col["perturbation_max"] }
    n[w]++; last[w] = $col["es_steps"]
    score[w] += $col["score"]; mean[w] += $col["perturbation_mean"]
    if ($col["perturbation_max"] > best[w]) best[w] = $col["perturbation_max"]
    if ($col["perturbation_max"] > threshold) above[w]++
    sigma[w] = $col["sigma"]; theta[w] = $col["theta_norm"]
  }
  END {
    if (bad) exit 2
    if (!windows) { printf "%s: no rows for pair %d\n", file, pair > "/dev/stderr"; exit 2 }
    printf "| ES steps | mean score | mean perturbation return | best perturbation | steps with one > %s | σ | ‖θ‖ |\n", threshold
    print "|---|---|---|---|---|---|---|"
    for (k = 1; k <= windows; k++) {
      w = order[k]
      printf "| %d–%d | %.1f | %.1f | %.1f | %d of %d | %.3f | %.2f |\n", first[w], last[w], score[w] / n[w],
             mean[w] / n[w], best[w], above[w], n[w], sigma[w], theta[w]
    }
  }' "$stats"
