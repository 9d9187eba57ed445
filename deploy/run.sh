#!/usr/bin/env bash
# Sets up a fresh Debian machine (dependencies, build) and runs the main job: one walker episode on an obstacle
# course, printed step by step and drawn to out/rollout.svg. Extra arguments go to poet-rollout (see --help).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/deploy/build.sh"
mkdir -p "$root/out"
"$root/build/coordinator/tools/poet-rollout" --course hardcore-like --seed 1 --random 7 \
  --picture "$root/out/rollout.svg" "$@"
