#!/usr/bin/env bash
# Installs every build and test dependency of poet from Debian's archive. Idempotent: packages already
# present are left alone, so the README, CI and the Dockerfile can all call it unconditionally.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libbox2d-dev libeigen3-dev
  libprotobuf-dev protobuf-compiler zlib1g-dev
  libzmq3-dev cppzmq-dev libcpp-httplib-dev
  libspdlog-dev libfmt-dev
  nlohmann-json3-dev libcli11-dev libcairo2-dev
  libgtest-dev libgmock-dev libbenchmark-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
