#!/usr/bin/env bash
# Ships what a POET run solved: a pair's environment and the agent that solved it, as data files, with the agent's
# scores over terrain seeds 0–49 and a GIF of it crossing its own course.
# Usage: bash experiments/ship_walker.sh BUILD_DIR RUN_DIR PAIR NAME
#   e.g. bash experiments/ship_walker.sh build runs/challenging 23 stumps-2.4
# Writes data/environments/NAME.env.json (the pair's course and terrain seed), data/walkers/NAME.json (the pair's
# best θ with its best score: the evaluation that solved it or a better one), docs/results/challenging/NAME.gif,
# adds NAME to data/walkers/shipped.json (walker, environment, the seeds it finishes on, which
# tests/unit/data/shipped_walkers_test.cpp checks) and prints its scores for data/walkers/README.md. Refuses an
# agent that does not finish its own course.
set -euo pipefail
usage="usage: bash experiments/ship_walker.sh BUILD_DIR RUN_DIR PAIR NAME"
build=${1:?$usage}
run=${2:?$usage}
pair=${3:?$usage}
name=${4:?$usage}
root=$(cd "$(dirname "$0")/.." && pwd)
[[ $pair =~ ^[0-9]+$ ]] || { echo "PAIR must be a pair id, got '$pair'" >&2; exit 2; }
[[ $name =~ ^[A-Za-z0-9._-]+$ ]] || { echo "NAME may hold letters, digits, '.', '_' and '-' only, got '$name'" >&2; exit 2; }
rollout=$build/tools/poet-rollout
eval_tool=$build/tools/poet-eval
for tool in "$rollout" "$eval_tool"; do [[ -x $tool ]] || { echo "no $tool: build first" >&2; exit 2; }; done
env_src=$run/envs/pair-$pair.env.json
walker_src=$run/policies/pair-$pair.best.json
for f in "$env_src" "$walker_src"; do [[ -f $f ]] || { echo "no $f: not a pair of a run directory" >&2; exit 2; }; done

env=$root/data/environments/$name.env.json
walker=$root/data/walkers/$name.json
gif=$root/docs/results/challenging/$name.gif
mkdir -p "$(dirname "$env")" "$(dirname "$gif")"
own=$("$rollout" --policy "$walker_src" --env "$env_src" --picture "" | grep '^return ')
[[ $own == *": finished"* ]] || { echo "pair $pair's best θ does not finish its own course: $own" >&2; exit 1; }
cp "$env_src" "$env"
cp "$walker_src" "$walker"
"$rollout" --policy "$walker" --env "$env" --picture "" --gif "$gif" >/dev/null
seed=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["seed"])' "$env")
sweep=$("$eval_tool" --policy "$walker" --env "$env" --seeds 0:49 --threads 2 --json - 2>/dev/null)

python3 - "$root/data/walkers/shipped.json" "$name" "$seed" "$own" "$sweep" <<'PY'
import json, os, sys
manifest, name, seed, own, sweep = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], json.loads(sys.argv[5])
c = sweep["courses"][0]
entries = json.load(open(manifest)) if os.path.exists(manifest) else []
entries = [e for e in entries if e["name"] != name]
seeds = sorted(set([seed] + c["finished_seeds"]))
entries.append({"name": name, "walker": "data/walkers/%s.json" % name,
                "environment": "data/environments/%s.env.json" % name, "finishes_on_seeds": seeds})
with open(manifest + ".tmp", "w") as f:
    json.dump(entries, f, indent=2)
    f.write("\n")
os.replace(manifest + ".tmp", manifest)
print("own course (terrain seed %d): %s" % (seed, own.strip()))
print("seeds 0-49: mean %.1f, min %.1f, max %.1f, finished %d, fell %d, timed out %d" % (
    c["mean_return"], c["min_return"], c["max_return"], c["finished"], c["fell"], c["timed_out"]))
print("finishes on seeds: %s" % seeds)
PY
echo "wrote $env, $walker, $gif and data/walkers/shipped.json"
