#!/usr/bin/env bash
# The paper's Figure 3 at small scale for one environment a POET run solved: the direct-path curriculum and ES alone,
# each from data/walkers/flat-walker.json (where the POET runs of this project start), with three seeds of their own
# (101, 102, 103: their ES noise and the direct path's stage draws), each within the budget of the environment's
# POET lineage (poet-lineage: the ES steps of its line of ancestors and of the agents it received by transfer, at
# the run's ES settings, so the same rollouts per step). Then poet-controls sets them beside the lineage (ES steps,
# environment steps, best score on the target, the closest solved environment and its normalised distance) and
# draws the rose: POET's environment in red, each control's closest solved environment in blue.
# Usage: bash experiments/figure3.sh BUILD_DIR RUN_DIR PAIR OUT_DIR [coordinator flags...]
#   e.g. nice bash experiments/figure3.sh build runs/deep 57 runs/figure3-57 --threads 2
# Each control runs in OUT_DIR/<control>-<seed>; running the script again resumes the ones not finished (runs are
# deterministic). Writes OUT_DIR/table.md, OUT_DIR/controls.json and OUT_DIR/rose.png, and prints the table.
set -euo pipefail
usage="usage: bash experiments/figure3.sh BUILD_DIR RUN_DIR PAIR OUT_DIR [coordinator flags...]"
third_tool=poet-controls
source "$(dirname "$0")/lineage_controls_args.sh"
controls=$build/tools/poet-controls

dirs=()
for seed in 101 102 103; do
  "$lineage" --run-dir "$run" --pair "$pair" --direct-path-config --seed "$seed" >"$out/direct-path-$seed.textproto"
  "$lineage" --run-dir "$run" --pair "$pair" --es-alone-config --seed "$seed" >"$out/es-alone-$seed.textproto"
  # the same command on a directory that holds this config's run resumes it (--start-from then has no effect); the
  # direct path stops by its own rule (target solved or budget spent), its iteration limit is only a bound
  "$coordinator" --config "$out/direct-path-$seed.textproto" --run-dir "$out/direct-path-$seed" --start-from "$walker" \
    --iterations $((budget * 2 + 10)) --quiet --status-address "" "$@" >>"$out/direct-path-$seed.log" 2>&1
  "$coordinator" --config "$out/es-alone-$seed.textproto" --run-dir "$out/es-alone-$seed" --start-from "$walker" \
    --quiet --status-address "" "$@" >>"$out/es-alone-$seed.log" 2>&1
  dirs+=("$out/direct-path-$seed" "$out/es-alone-$seed")
done
"$controls" --run-dir "$run" --pair "$pair" "${dirs[@]}" --json "$out/controls.json"
"$controls" --run-dir "$run" --pair "$pair" "${dirs[@]}" --rose "$out/rose.png" | tee "$out/table.md"
