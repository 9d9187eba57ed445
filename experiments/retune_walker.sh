#!/usr/bin/env bash
# Re-tunes a shipped walker to its own course under this build: ES alone on the walker's course (its encoding and
# terrain seed, data/environments/NAME.env.json) from its θ (data/walkers/NAME.json), with small steps (σ 0.02,
# 32 mirrored pairs, lr 0.005), stopping at the first evaluation that solves the course (finished, ≥ 230) or after
# ITERATIONS ES steps; then ships the solving θ with experiments/ship_walker.sh (which refuses one that does not
# finish its course). For walkers whose course a build that computes other last bits no longer sees them cross:
# a walking gait on a frontier course is chaotic, and 2,000 steps amplify a last-bit difference into another
# trajectory. The GIF ship_walker.sh writes is restored to the committed one (the results pages show the run's).
# Usage: bash experiments/retune_walker.sh BUILD_DIR NAME RUN_DIR [ITERATIONS]   (default 60; --threads 2)
#   e.g. bash experiments/retune_walker.sh build poet-17-r4.8 runs/retune-poet-17-r4.8
set -euo pipefail
usage="usage: bash experiments/retune_walker.sh BUILD_DIR NAME RUN_DIR [ITERATIONS]"
build=${1:?$usage}
name=${2:?$usage}
run=${3:?$usage}
iterations=${4:-60}
root=$(cd "$(dirname "$0")/.." && pwd)
coordinator=$build/coordinator/poet-coordinator
[[ -x $coordinator ]] || { echo "no $coordinator: build first" >&2; exit 2; }
[[ $iterations =~ ^[1-9][0-9]*$ ]] || { echo "ITERATIONS must be a positive number, got '$iterations'" >&2; exit 2; }
env=$root/data/environments/$name.env.json
walker=$root/data/walkers/$name.json
for f in "$env" "$walker"; do [[ -f $f ]] || { echo "no $f: not a shipped walker" >&2; exit 2; }; done
[[ ! -e $run ]] || { echo "$run exists: give a new run directory" >&2; exit 2; }

config=$(mktemp --suffix=.textproto)
trap 'rm -f "$config"' EXIT
python3 - "$env" "$iterations" >"$config" <<'PY'
import json, sys
env, iterations = json.load(open(sys.argv[1])), int(sys.argv[2])
c = env["config"]
def interval(key, field):
    v = c.get(key) or []
    return f"      {field} {{ lo: {v[0]!r} hi: {v[1]!r} }}\n" if v else ""
print(f"""mode: ES_ALONE
seed: 2
iterations: {iterations}
es {{ perturbations: 32 init_sigma: 0.02 init_lr: 0.005 }}
es_alone {{
  stop_when_solved: true
  target {{
    encoding {{
      name: {json.dumps(c["name"])}
      roughness: {c.get("ground_roughness", 0)!r}
{interval("pit_gap", "pit_gap")}{interval("stump_width", "stump_width")}{interval("stump_height", "stump_height")}{interval("stump_float", "stump_float")}{interval("stair_height", "stair_height")}{interval("stair_width", "stair_width")}{interval("stair_steps", "stair_steps")}    }}
    seed: {env["seed"]}
  }}
}}""")
PY
"$coordinator" --config "$config" --run-dir "$run" --start-from "$walker" --threads 2 --quiet
gif=docs/results/challenging/$name.gif
bash "$root/experiments/ship_walker.sh" "$build" "$run" 0 "$name"
git -C "$root" checkout -- "$gif" 2>/dev/null || true
