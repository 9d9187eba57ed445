#!/usr/bin/env bash
# Two builds of dispatch_bench, side by side: its rows that time the coordinator's side (BM_DispatcherAlone: the
# Dispatcher alone, no sockets; BM_DispatchCapacity: a RemoteEvaluator and in-process workers over loopback) with the
# program BEFORE and the program AFTER, run alternately ROUNDS times each in one run, so that a change in the
# machine's load falls on both. Prints, per row, the median results per second of each and their ratio (after /
# before), with the machine's load before and after, as a Markdown table. Keep a build's program aside
# (cp build/bench/dispatch_bench /tmp/before), change and rebuild, then compare.
#   bash bench/dispatch_compare.sh BEFORE AFTER [ROUNDS [ROWS]]      default 7 rounds, ROWS a regex of rows
set -euo pipefail
usage_error() {
  echo "dispatch_compare.sh: $*" >&2
  echo "usage: bash bench/dispatch_compare.sh BEFORE AFTER [ROUNDS [ROWS]]" >&2
  exit 2
}
[ $# -ge 2 ] || usage_error "expected two dispatch_bench programs"
for program in "$1" "$2"; do
  [ -x "$program" ] || usage_error "$program is not an executable (build with deploy/build.sh)"
done
rounds=${3:-7}
rows=${4:-'BM_Dispatch(erAlone|Capacity)/'}
[[ $rounds =~ ^[1-9][0-9]*$ ]] || usage_error "ROUNDS must be a positive number (got $rounds)"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

source "$(dirname "$0")/alternate.sh"
alternate_rounds "$rounds" "$scratch" "before=$1" "after=$2" -- "--benchmark_filter=$rows"

python3 - "$scratch" "$rounds" "$load_before" "$load_after" <<'PY'
import json, statistics, sys
scratch, rounds, before, after = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
rates = {}
order = []
for side in ("before", "after"):
    for r in range(1, rounds + 1):
        with open(f"{scratch}/{side}-{r}.json") as f:
            for b in json.load(f)["benchmarks"]:
                if b["name"] not in order:
                    order.append(b["name"])
                rates.setdefault((b["name"], side), []).append(b["items_per_second"])
print(f"{rounds} alternated rounds of each; load average before {before}, after {after}\n")
print("| row | before, results/s | after, results/s | after / before |")
print("|---|---|---|---|")
for name in order:
    old = statistics.median(rates[(name, "before")])
    new = statistics.median(rates[(name, "after")])
    print(f"| {name} | {old:,.0f} | {new:,.0f} | {new / old:.3f} |")
PY
