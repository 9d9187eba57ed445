#!/usr/bin/env bash
# Installs the dependencies of poet from Debian's archive. Idempotent: packages already present are left alone,
# so the README, CI and the Dockerfile can all call it unconditionally.
#   install-deps.sh             every build and test dependency (the default)
#   install-deps.sh --build     what a build without tests and benchmarks needs (the Docker image's build stage)
#   install-deps.sh --runtime   only the shared libraries the built binaries load (the Docker image's runtime stage)
#   add --list to print the selected packages, one a line, and install nothing
# The runtime names carry the libraries' sonames of Debian 12 (bookworm); tests/deploy checks them against the
# libraries the binaries actually link.
set -euo pipefail

build_packages=(
  build-essential cmake pkg-config
  libbox2d-dev libeigen3-dev
  libprotobuf-dev protobuf-compiler zlib1g-dev
  libzmq3-dev cppzmq-dev libcpp-httplib-dev libmicrohttpd-dev
  libspdlog-dev libfmt-dev
  nlohmann-json3-dev libcli11-dev libcairo2-dev libgif-dev
  # the Python module (python/): pybind11 and Debian's Python headers; numpy at import; tqdm for poet.start's
  # progress bar (optional: without it the progress is a line of text)
  pybind11-dev python3-dev python3-numpy python3-tqdm
)

test_packages=(
  libgtest-dev libgmock-dev libbenchmark-dev
  # the deploy tests: the compose file is checked with Debian's docker-compose, the manifests with PyYAML, and
  # the coordinator's healthcheck (curl on /healthz) is run as written
  docker-compose python3-yaml curl
  # deploy/bundle.sh points the bundle's binaries and libraries at each other with it (the deploy_bundle test)
  patchelf
  # the dashboard tests: the status page in headless chromium, driven by its WebDriver (same version)
  chromium chromium-driver
  # the Python module's tests (pytest) and examples (pandas, matplotlib)
  python3-pytest python3-pandas python3-matplotlib
  # the documentation site (mkdocs.yml): built with --strict by the tests, so a broken link or anchor fails them
  mkdocs mkdocs-material
  # the cluster tests: hosts as network namespaces on a bridge, links cut and shaped (ip, tc)
  iproute2
)

runtime_packages=(
  libc6 libgcc-s1 libstdc++6 zlib1g
  libbox2d2 libprotobuf32 libzmq5 libcpp-httplib0.11 libmicrohttpd12
  libspdlog1.10 libfmt9 libcairo2 libgif7
)

set_name=all
list=0
for arg in "$@"; do
  case "$arg" in
    --build) set_name=build ;;
    --runtime) set_name=runtime ;;
    --list) list=1 ;;
    -h | --help)
      sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    *)
      echo "install-deps: unknown option $arg (expected --build, --runtime, --list)" >&2
      exit 2
      ;;
  esac
done

case "$set_name" in
  build) packages=("${build_packages[@]}") ;;
  runtime) packages=("${runtime_packages[@]}") ;;
  all) packages=("${build_packages[@]}" "${test_packages[@]}") ;;
esac
if [ "$list" -eq 1 ]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

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
