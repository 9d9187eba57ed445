#!/usr/bin/env bash
# Sets up a fresh Debian machine (dependencies, build) and runs the main job: POET with the `quick` preset on
# this machine's cores, into out/quick, its first pair starting from the shipped walker (data/walkers). Interrupted (Ctrl-C), it stops at once with its last checkpoint as the
# state; run this again to resume.
# Extra arguments go to poet-coordinator (see --help), e.g. --threads 2 or --iterations 60.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/deploy/build.sh"
run_dir="${POET_RUN_DIR:-$root/out/quick}"
mkdir -p "$(dirname "$run_dir")"
# a directory that holds a run of this config is resumed; rollouts run on two local worker processes
exec "$root/build/coordinator/poet-coordinator" --config "$root/deploy/configs/quick.textproto" \
  --run-dir "$run_dir" --start-from "$root/data/walkers/flat-walker.json" --local-workers 2 "$@"
