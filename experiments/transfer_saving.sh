#!/usr/bin/env bash
# What Enhanced POET's threshold transfer test saves, measured: the same config run twice, once with the paper's
# full transfer test and once with poet.transfer_test THRESHOLD_TRANSFER_TEST (set in a copy of the config), and the
# rollouts each transfer round ran as its transfer_round event records them. The two runs are the same until their
# first round; after it they differ (different transfers are accepted), so rounds are compared at equal numbers of
# active pairs N, whose full test always tries N(N−1) candidates.
# Usage: bash experiments/transfer_saving.sh BUILD_DIR CONFIG OUT_DIR [coordinator flags...]
#   e.g. bash experiments/transfer_saving.sh build deploy/configs/quick.textproto runs/transfer-quick \
#          --start-from data/walkers/flat-walker.json --iterations 13 --threads 1
# The runs are OUT_DIR/full and OUT_DIR/threshold; running the script again resumes them (runs are deterministic).
# Prints experiments/transfer_rounds.sh's tables of both runs: each round of each, then rollouts per round at each N.
set -euo pipefail
usage="usage: bash experiments/transfer_saving.sh BUILD_DIR CONFIG OUT_DIR [coordinator flags...]"
build=${1:?$usage}
config=${2:?$usage}
out=${3:?$usage}
shift 3
coordinator=$build/coordinator/poet-coordinator
[[ -x $coordinator ]] || { echo "no $coordinator: build first" >&2; exit 2; }
[[ -f $config ]] || { echo "no config $config" >&2; exit 2; }
mkdir -p "$out"

for test in full threshold; do
  # the config with transfer_test set in its poet block (one is added when the config has none)
  python3 - "$config" "$test" >"$out/$test.textproto" <<'PY'
import re, sys
text, test = open(sys.argv[1]).read(), sys.argv[2]
value = "THRESHOLD_TRANSFER_TEST" if test == "threshold" else "FULL_TRANSFER_TEST"
text = re.sub(r"^\s*transfer_test\s*:.*\n", "", text, flags=re.M)
text, found = re.subn(r"^(\s*poet\s*\{)", r"\1\n  transfer_test: " + value, text, count=1, flags=re.M)
if not found:
    text += "\npoet { transfer_test: %s }\n" % value
sys.stdout.write(text)
PY
  # the same command on a directory that holds this config's run resumes it (--start-from then has no effect)
  "$coordinator" --config "$out/$test.textproto" --run-dir "$out/$test" --quiet --status-address "" "$@" \
    >>"$out/$test.log" 2>&1
done

bash "$(dirname "$0")/transfer_rounds.sh" "$out/full" "$out/threshold"
