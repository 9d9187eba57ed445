#!/usr/bin/env bash
# What the project's own math costs a rollout: walker_bench's rollout rows (BM_Rollout/<course>: 128 random
# policies' episodes on each of four courses, policy, lidar and Box2D; BM_RolloutSet/flat_set:k: flat's 128 in eight
# sets of 16; BM_WalkerRollout/flat and /r1: the shipped flat walker on 8 terrain seeds) with the project's exp, log,
# sin and cos, and the same program with the C library's (walker_bench_libm), run alternately ROUNDS times each in
# one run, so that a change in the machine's load falls on both. Prints, per row, the median steps per second of
# each and their ratio, with the machine's load before and after, as a Markdown table. The two builds compute other
# last bits, so they walk other episodes, and a step's cost follows its contacts: the sets of 16 show how far one
# small set of episodes moves the ratio either way, the rows of 128 what is left of it (the steps column says how
# long the episodes were).
#   bash bench/math_cost.sh BUILD_DIR [ROUNDS]      default 5 rounds
set -euo pipefail
usage_error() {
  echo "math_cost.sh: $*" >&2
  echo "usage: bash bench/math_cost.sh BUILD_DIR [ROUNDS]" >&2
  exit 2
}
[ $# -ge 1 ] || usage_error "expected BUILD_DIR"
build=$(cd "$1" 2>/dev/null && pwd) || usage_error "$1 is not a directory"
rounds=${2:-5}
[[ $rounds =~ ^[1-9][0-9]*$ ]] || usage_error "ROUNDS must be a positive number (got $rounds)"
for program in walker_bench walker_bench_libm; do
  [ -x "$build/bench/$program" ] || usage_error "$build/bench/$program is missing (build with deploy/build.sh)"
done
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

source "$(dirname "$0")/alternate.sh"
alternate_rounds "$rounds" "$scratch" "walker_bench=$build/bench/walker_bench" \
  "walker_bench_libm=$build/bench/walker_bench_libm" -- '--benchmark_filter=BM_(Walker)?Rollout(Set)?/' \
  --benchmark_min_time=2

python3 - "$scratch" "$rounds" "$load_before" "$load_after" <<'PY'
import json, statistics, sys
scratch, rounds, before, after = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
rates = {}
steps = {}
for program in ("walker_bench", "walker_bench_libm"):
    for r in range(1, rounds + 1):
        with open(f"{scratch}/{program}-{r}.json") as f:
            for b in json.load(f)["benchmarks"]:
                rates.setdefault((b["name"], program), []).append(b["steps_per_s"])
                steps[(b["name"], program)] = b["steps"]
rows = sorted({name for name, _ in rates})
print(f"{rounds} alternated rounds of each; load average before {before}, after {after}\n")
print("| row | project's math, steps/s | C library's, steps/s | ratio | steps (project's, C library's) |")
print("|---|---|---|---|---|")
for name in rows:
    own = statistics.median(rates[(name, "walker_bench")])
    libm = statistics.median(rates[(name, "walker_bench_libm")])
    print(f"| {name} | {own:,.0f} | {libm:,.0f} | {own / libm:.3f} | "
          f"{steps[(name, 'walker_bench')]:,.0f}, {steps[(name, 'walker_bench_libm')]:,.0f} |")
PY
