#!/usr/bin/env bash
# The paper's controls on an environment POET solved (spec §3), each with the budget POET spent on it: the ES steps
# of the environment's line of ancestors and of the agents it received by transfer (poet-lineage), at the run's
# own ES settings, so the controls and POET's lineage take the same number of ES steps and rollouts.
#   es-alone-random   ES alone from random θ (the paper's control)
#   es-alone-walker   ES alone from data/walkers/flat-walker.json (where the POET run started; the paper did not
#                     run it)
#   direct-path       the direct-path curriculum from flat to the environment, from the same walker
# Usage: bash experiments/controls.sh BUILD_DIR RUN_DIR PAIR OUT_DIR [coordinator flags...]
#   e.g. bash experiments/controls.sh build runs/challenging 23 runs/controls-23 --threads 2
# Each control runs in OUT_DIR/<control>; running the script again resumes the ones not finished (runs are
# deterministic, so an interrupted control gives the same numbers). Prints a Markdown table: the ES steps,
# rollouts and environment steps each control used, its best score on the target (and whether that evaluation
# finished), and whether it solved it (finished and ≥ the solved score); for the direct path, the stage reached.
set -euo pipefail
usage="usage: bash experiments/controls.sh BUILD_DIR RUN_DIR PAIR OUT_DIR [coordinator flags...]"
third_tool=poet-report
source "$(dirname "$0")/lineage_controls_args.sh"
report=$build/tools/poet-report
"$lineage" --run-dir "$run" --pair "$pair" --es-alone-config >"$out/es-alone.textproto"
"$lineage" --run-dir "$run" --pair "$pair" --direct-path-config >"$out/direct-path.textproto"

control() {  # NAME CONFIG [flags]: runs (or resumes) one control to its end
  local name=$1 config=$2
  shift 2
  # the same command on a directory that holds this config's run resumes it (--start-from then has no effect)
  "$coordinator" --config "$config" --run-dir "$out/$name" --quiet --status-address "" "$@" >>"$out/$name.log" 2>&1
}
control es-alone-random "$out/es-alone.textproto" "$@"
control es-alone-walker "$out/es-alone.textproto" --start-from "$walker" "$@"
# the direct path stops by its own rule (target solved or budget spent); its iteration limit is only a bound
control direct-path "$out/direct-path.textproto" --start-from "$walker" --iterations $((budget * 2 + 10)) "$@"

echo "Controls for pair $pair of $run ($(sed -n 's/^  *name: "\(.*\)"$/\1/p' "$out/es-alone.textproto" | head -1)), budget $budget ES steps"
echo
echo "| control | ES steps | rollouts | environment steps | best score | solved |"
echo "|---|---|---|---|---|---|"
for name in es-alone-random es-alone-walker direct-path; do
  "$report" --run-dir "$out/$name" --json - | python3 -c '
import csv, json, sys
name = sys.argv[1]
r = json.load(sys.stdin)
p = r["pairs"][0]
if r["mode"] == "direct-path curriculum":
    # the target is solved when the closest solved stage is the target itself; the best score on it is read from
    # the evaluations made while the curriculum stood there
    t = r.get("closest_to_target") or {}
    d = t.get("distance")
    with open(sys.argv[2]) as f:
        on_target = [float(row["score"]) for row in csv.DictReader(f) if row["env"] == t.get("target")]
    best = "%.1f on the target (%d ES steps there)" % (max(on_target), len(on_target)) if on_target else "never reached the target"
    solved = "yes" if d == 0 else "no; closest solved stage %s, normalised distance %s" % (
        t.get("closest_solved") or "none", "%.3f" % d if d is not None else "-")
else:
    best = "%.1f" % p["best_score"]
    solved = "yes, at ES step %d" % (p["solved"] + 1) if p["solved"] is not None else "no"
print("| %s | %d | %d | %.1f M | %s | %s |" % (name, p["es_steps"], r["rollouts"], r["env_steps"] / 1e6, best, solved))
' "$name" "$out/$name/pair_stats.csv"
done
