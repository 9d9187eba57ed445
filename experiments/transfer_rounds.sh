#!/usr/bin/env bash
# What a run's transfer rounds cost, from its transfer_round events: per round the candidates (N(N−1) source →
# target pairs), the proposal ES steps paid for, the accepted transfers, and the rollouts it ran (recorded in the
# event; for runs from before it was, the formula) against those of the full test (each candidate: a direct
# evaluation, a proposal ES step of 2n rollouts and the proposal's evaluation). Given several runs, it adds their
# rollouts per round side by side at each number of active pairs N (experiments/transfer_saving.sh runs one config
# with both tests and passes both runs here).
# Usage: bash experiments/transfer_rounds.sh RUN_DIR [RUN_DIR...]
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: bash experiments/transfer_rounds.sh RUN_DIR [RUN_DIR...]" >&2; exit 2; }
for run in "$@"; do
  [[ -f $run/events.jsonl && -f $run/config.textproto ]] || { echo "$run is not a run directory" >&2; exit 2; }
done
python3 - "$@" <<'PY'
import json, os, re, sys
from collections import defaultdict

def perturbations(run):
    with open(run + "/config.textproto") as f:
        found = re.search(r"^\s*perturbations:\s*(\d+)", f.read(), re.M)
    return int(found.group(1)) if found else 256  # the schema's default

def rounds(run):
    path, rows = run + "/events.jsonl", []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            try:
                e = json.loads(line)
            except json.JSONDecodeError:
                sys.exit("%s:%d: not JSON" % (path, number))
            if e.get("event") == "transfer_round":
                rows.append(e)
    if not rows:
        sys.exit("%s: no transfer_round events (a run from before they were written, or one without transfers)" % path)
    return rows

runs = {run: rounds(run) for run in sys.argv[1:]}
for run, rows in runs.items():
    n = perturbations(run)
    if len(runs) > 1:
        print("%s\n" % run)
    print("| iteration | test | pairs | candidates | proposals | accepted | rollouts | full test's rollouts |")
    print("|---|---|---|---|---|---|---|---|")
    paid = full = 0
    for e in rows:
        c, p = e["candidates"], e["proposals"]
        # the round's own count where its event records it; earlier runs' events give it by the formula
        r = e.get("rollouts", c + p * (2 * n + 1) if e["test"] == "threshold" else c * (2 * n + 2))
        f = c * (2 * n + 2)
        e["rollouts"] = r
        paid, full = paid + r, full + f
        print("| %d | %s | %d | %d | %d | %d | %d | %d |" % (e["iteration"], e["test"], e["pairs"], c, p, e["accepted"],
                                                            r, f))
    print()
    print("%d rounds: %d rollouts, against %d with the full test (%.1f %%)" % (len(rows), paid, full,
                                                                            100.0 * paid / full))
    print()

if len(runs) > 1:
    # rounds at equal N side by side: mean rollouts per round in each run, and as a share of the first run's
    names = list(runs)
    labels = [os.path.basename(os.path.normpath(r)) for r in names]  # a run by its directory's name while they differ
    label = dict(zip(names, labels if len(set(labels)) == len(labels) else names))
    by_n = defaultdict(lambda: defaultdict(list))
    for run, rows in runs.items():
        for e in rows:
            by_n[e["pairs"]][run].append(e["rollouts"])
    print("| N | candidates | " + " | ".join("%s: rounds, rollouts per round" % label[r] for r in names) + " | " +
          " | ".join("%s / %s" % (label[r], label[names[0]]) for r in names[1:]) + " |")
    print("|---|---|" + "---|" * (2 * len(names) - 1))
    for n in sorted(by_n):
        means = {r: sum(v) / len(v) for r, v in by_n[n].items()}
        cells = ["%d, %.0f" % (len(by_n[n][r]), means[r]) if r in means else "0, -" for r in names]
        shares = ["%.1f %%" % (100 * means[r] / means[names[0]]) if r in means and names[0] in means else "-"
                  for r in names[1:]]
        print("| %d | %d | %s | %s |" % (n, n * (n - 1), " | ".join(cells), " | ".join(shares)))
PY
