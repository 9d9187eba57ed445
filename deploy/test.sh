#!/usr/bin/env bash
# Sets up a fresh Debian machine (dependencies, build) and runs every test. CI runs exactly this.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/deploy/build.sh"
cd "$root/build"
ctest --output-on-failure -j"$(nproc)" "$@"
