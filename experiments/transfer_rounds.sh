#!/usr/bin/env bash
# What a run's transfer rounds cost, from its transfer_round events: per round the candidates (N(N−1) source →
# target pairs), the proposal ES steps paid for, the accepted transfers, and the rollouts against those of the full
# test (each candidate: a direct evaluation, a proposal ES step of 2n rollouts and the proposal's evaluation).
# Usage: bash experiments/transfer_rounds.sh RUN_DIR
set -euo pipefail
run=${1:?usage: bash experiments/transfer_rounds.sh RUN_DIR}
[[ -f $run/events.jsonl && -f $run/config.textproto ]] || { echo "$run is not a run directory" >&2; exit 2; }
n=$(sed -n 's/^ *perturbations: *\([0-9]*\).*/\1/p' "$run/config.textproto" | head -1)
n=${n:-256}  # the schema's default
python3 - "$run/events.jsonl" "$n" <<'PY'
import json, sys
path, n = sys.argv[1], int(sys.argv[2])
rows = []
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
print("| iteration | test | pairs | candidates | proposals | accepted | rollouts | full test's rollouts |")
print("|---|---|---|---|---|---|---|---|")
paid = full = 0
for e in rows:
    c, p = e["candidates"], e["proposals"]
    r = c + p * (2 * n + 1) if e["test"] == "threshold" else c * (2 * n + 2)
    f = c * (2 * n + 2)
    paid, full = paid + r, full + f
    print("| %d | %s | %d | %d | %d | %d | %d | %d |" % (e["iteration"], e["test"], e["pairs"], c, p, e["accepted"], r, f))
print()
print("%d rounds: %d rollouts, against %d with the full test (%.1f %%)" % (len(rows), paid, full, 100.0 * paid / full))
PY
