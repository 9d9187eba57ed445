#!/usr/bin/env bash
# Installs the dependencies (if missing) and builds everything into build/ (Release). Idempotent.
#   deploy/build.sh --image [TAG]   instead builds the image (deploy/Dockerfile, default tag poet), labelled with
#                                   the project's version
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [[ ${1:-} == --image ]]; then
  exec docker build --network host -f "$root/deploy/Dockerfile" -t "${2:-poet}" "$root"
fi
bash "$root/deploy/install-deps.sh"
# POET_REFERENCE_DIR in the environment: the optional reference data for the alignment tests (tests/README.md)
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release \
      ${POET_REFERENCE_DIR:+-DPOET_REFERENCE_DIR="$POET_REFERENCE_DIR"} >/dev/null
cmake --build "$root/build" -j"$(nproc)"
