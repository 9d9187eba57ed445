#!/usr/bin/env bash
# Agents that generalise, the comparison the field makes: POET on fixed courses, POET on stochastic courses and
# domain randomisation (ES from the walker on courses drawn at the level POET reached), each from
# data/walkers/flat-walker.json to the same budget of environment steps (experiments/general/*.textproto), then
# every agent of each run and the flat walker on the held-out test suite (poet-eval --suite). For POET the best
# single agent of the run (every pair's θ and best θ is a candidate) and the best per level.
# Usage: bash experiments/general.sh BUILD_DIR OUT_DIR [coordinator flags...]
#   e.g. nice bash experiments/general.sh build runs/general --threads 2
# Each run lives in OUT_DIR/<name>; running the script again resumes those not finished (runs are deterministic;
# a run moved between machines is restored with poetctl unpack first). Writes OUT_DIR/<name>.suite.json and
# OUT_DIR/flat-walker.suite.json, then experiments/general_table.py's table (OUT_DIR/table.md) and plot
# (OUT_DIR/suite.png).
set -euo pipefail
usage="usage: bash experiments/general.sh BUILD_DIR OUT_DIR [coordinator flags...]"
build=${1:?$usage}
out=${2:?$usage}
shift 2
root=$(cd "$(dirname "$0")/.." && pwd)
coordinator=$build/coordinator/poet-coordinator
eval_bin=$build/tools/poet-eval
for tool in "$coordinator" "$eval_bin"; do [[ -x $tool ]] || { echo "no $tool: build first" >&2; exit 2; }; done
walker=$root/data/walkers/flat-walker.json
suite=poet-suite-v1
mkdir -p "$out"

for name in fixed stochastic domain-randomisation; do
  dir=$out/$name
  if [[ -f $dir/checkpoint.pb ]]; then
    "$coordinator" --run-dir "$dir" --resume --quiet --status-address "" "$@" >>"$out/$name.log" 2>&1
  else
    "$coordinator" --config "$root/experiments/general/$name.textproto" --run-dir "$dir" --start-from "$walker" \
      --quiet --status-address "" "$@" >>"$out/$name.log" 2>&1
  fi
  "$eval_bin" --run-dir "$dir" --suite "$suite" --json "$out/$name.suite.json" >"$out/$name.suite.txt"
done
"$eval_bin" --policy "$walker" --suite "$suite" --json "$out/flat-walker.suite.json" >"$out/flat-walker.suite.txt"
/usr/bin/python3 "$root/experiments/general_table.py" --plot "$out/suite.png" \
  "POET, fixed courses=$out/fixed.suite.json" "POET, stochastic courses=$out/stochastic.suite.json" \
  "domain randomisation=$out/domain-randomisation.suite.json" "flat walker=$out/flat-walker.suite.json" |
  tee "$out/table.md"
