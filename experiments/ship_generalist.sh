#!/usr/bin/env bash
# Ships a walker judged by a held-out test suite: the policy, its suite figures, a GIF of it finishing a suite
# course and the episodes a test replays.
# Usage: bash experiments/ship_generalist.sh BUILD_DIR POLICY NAME [SUITE]
#   e.g. bash experiments/ship_generalist.sh build runs/general/stochastic/policies/pair-13.best.json stochastic-13
# Runs POLICY on SUITE (default poet-suite-v1) and writes data/walkers/NAME.json (the policy), the course of the
# GIF as data/environments/NAME.COURSE.env.json (the first course it finishes in the hardest group where it finishes
# one), docs/results/general/NAME.gif, and NAME's entry in data/walkers/generalists.json: the suite's figures per
# group and a subset of its episodes — every episode it finishes and each group's first two — which
# tests/unit/data/generalist_walkers_test.cpp replays. Prints the figures for data/walkers/README.md. Refuses a
# policy that finishes no course of the suite.
set -euo pipefail
usage="usage: bash experiments/ship_generalist.sh BUILD_DIR POLICY NAME [SUITE]"
build=${1:?$usage}
policy=${2:?$usage}
name=${3:?$usage}
suite=${4:-poet-suite-v1}
root=$(cd "$(dirname "$0")/.." && pwd)
[[ $name =~ ^[A-Za-z0-9._-]+$ ]] || { echo "NAME may hold letters, digits, '.', '_' and '-' only, got '$name'" >&2; exit 2; }
rollout=$build/tools/poet-rollout
eval_tool=$build/tools/poet-eval
for tool in "$rollout" "$eval_tool"; do [[ -x $tool ]] || { echo "no $tool: build first" >&2; exit 2; }; done
[[ -f $policy ]] || { echo "no policy file $policy" >&2; exit 2; }

walker=data/walkers/$name.json
gif=docs/results/general/$name.gif
scores=$(mktemp)
trap 'rm -f "$scores"' EXIT
"$eval_tool" --policy "$policy" --suite "$suite" --threads 2 --json "$scores" >/dev/null
mkdir -p "$root/data/environments" "$root/$(dirname "$gif")"
# The manifest entry and the GIF's course; prints the course's env file.
env=$(/usr/bin/python3 - "$root" "$name" "$walker" "$scores" <<'PY'
import json, os, sys
root, name, walker, scores = sys.argv[1:5]
score = json.load(open(scores))
finished = [(g, c, e) for g in score["groups"] for c in g["courses"] for e in c["episodes"] if e["finished"]]
if not finished:
    sys.exit("the policy finishes no course of %s: nothing to ship" % score["suite"])
order = ["extremely challenging", "very challenging", "challenging", "hardcore-like", "easy"]
group, course, episode = min(finished, key=lambda f: order.index(f[0]["group"]) if f[0]["group"] in order else len(order))
env = "data/environments/%s.%s.env.json" % (name, course["course"])
with open(os.path.join(root, env), "w") as f:
    json.dump({"config": course["config"], "seed": episode["seed"]}, f, indent=2)
    f.write("\n")
subset = []
for g in score["groups"]:
    episodes = [(c, e) for c in g["courses"] for e in c["episodes"]]
    for i, (c, e) in enumerate(episodes):
        if e["finished"] or i < 2:
            subset.append({"group": g["group"], "course": c["course"], "seed": e["seed"], "finished": e["finished"],
                           "return": e["return"], "steps": e["steps"]})
keys = ("episodes", "finished", "mean_progress", "mean_return")
entry = {"name": name, "walker": walker, "suite": score["suite"], "gif_course": env,
         "figures": [dict({"group": g["group"]}, **{k: g[k] for k in keys}) for g in score["groups"]],
         "replay": subset}
manifest = os.path.join(root, "data/walkers/generalists.json")
entries = json.load(open(manifest)) if os.path.exists(manifest) else []
entries = [e for e in entries if e["name"] != name] + [entry]
with open(manifest + ".tmp", "w") as f:
    json.dump(entries, f, indent=2)
    f.write("\n")
os.replace(manifest + ".tmp", manifest)
print("| group | finished | mean progress | mean return |", file=sys.stderr)
print("|---|---|---|---|", file=sys.stderr)
for g in score["groups"]:
    print("| %s | %d of %d | %.1f %% | %.1f |" % (g["group"], g["finished"], g["episodes"], 100 * g["mean_progress"],
                                               g["mean_return"]), file=sys.stderr)
print("| all | %d of %d | %.1f %% | %.1f |" % (score["finished"], score["episodes"], 100 * score["mean_progress"],
                                            score["mean_return"]), file=sys.stderr)
print(env)
PY
)
cp "$policy" "$root/$walker"
"$rollout" --policy "$root/$walker" --env "$root/$env" --picture "" --gif "$root/$gif" | grep '^return '
echo "wrote $walker, $env, $gif and data/walkers/generalists.json"
