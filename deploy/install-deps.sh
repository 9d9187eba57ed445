#!/usr/bin/env bash
# Installs the dependencies of poet from Debian's archive. Idempotent: packages already present are left alone,
# so the README, CI and the Dockerfile can all call it unconditionally.
#   install-deps.sh             every build and test dependency (the default)
#   install-deps.sh --build     what a build without tests and benchmarks needs (the Docker image's build stage)
#   install-deps.sh --runtime   only the shared libraries the built binaries load (the Docker image's runtime stage)
#   install-deps.sh --crossmachine   what the crossmachine tests need (tests/crossmachine): debootstrap,
#                               qemu-user-static, the aarch64 cross compiler and arm64's -dev packages (multiarch)
#   add --list to print the selected packages, one a line, and install nothing
# The default and --build also install Box2D's source, which the build compiles: Debian's source package
# (third_party/box2d/fetch-source.sh, into /usr/local/src/poet; a no-op once there).
# The runtime names carry the libraries' sonames of Debian 12 (bookworm); tests/deploy checks them against the
# libraries the binaries actually link.
set -euo pipefail

build_packages=(
  build-essential cmake pkg-config
  # Box2D is no package here: the build compiles Debian's source package, which dpkg-source unpacks (below)
  dpkg-dev
  libeigen3-dev
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
  # the SLURM tests (tests/slurm): a real cluster on this machine, slurmctld and slurmd nodes authenticated by munge
  slurm-wlm munge
)

runtime_packages=(
  libc6 libgcc-s1 libstdc++6 zlib1g
  libprotobuf32 libzmq5 libcpp-httplib0.11 libmicrohttpd12
  libspdlog1.10 libfmt9 libcairo2 libgif7
)

# --crossmachine (tests/crossmachine/README.md): a Debian 13 root made by debootstrap, into which the bundle goes
# (deploy/bundle.sh: patchelf); the project cross-built for arm64 by Debian's aarch64 cross compiler against the
# arm64 builds of the libraries it links (Debian's multiarch: the arm64 packages beside the amd64 ones, at the same
# versions, so apt may upgrade an amd64 library to its archive version), and run by qemu's user-mode emulator.
# No binfmt-support: the tests call qemu-aarch64-static by name; registering it with binfmt_misc would change how
# the whole machine's kernel starts arm64 programs.
crossmachine_packages=(
  debootstrap debian-archive-keyring patchelf
  g++-aarch64-linux-gnu qemu-user-static
  # the host's own, for the cross build: CMake, protoc (the host's generates the code for both), header-only
  # libraries, and Box2D's source (below)
  cmake pkg-config protobuf-compiler libeigen3-dev nlohmann-json3-dev libcli11-dev dpkg-dev
  # arm64's C and C++ runtime (the loader /lib/ld-linux-aarch64.so.1 that qemu starts), and the -dev packages
  libc6:arm64 libstdc++6:arm64
  libprotobuf-dev:arm64 zlib1g-dev:arm64 libzmq3-dev:arm64 cppzmq-dev:arm64 libcpp-httplib-dev:arm64
  libmicrohttpd-dev:arm64 libspdlog-dev:arm64 libfmt-dev:arm64 libcairo2-dev:arm64 libgif-dev:arm64
  libgtest-dev:arm64 libgmock-dev:arm64
)

set_name=all
list=0
for arg in "$@"; do
  case "$arg" in
    --build) set_name=build ;;
    --runtime) set_name=runtime ;;
    --crossmachine) set_name=crossmachine ;;
    --list) list=1 ;;
    -h | --help)
      sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    *)
      echo "install-deps: unknown option $arg (expected --build, --runtime, --crossmachine, --list)" >&2
      exit 2
      ;;
  esac
done

case "$set_name" in
  build) packages=("${build_packages[@]}") ;;
  runtime) packages=("${runtime_packages[@]}") ;;
  crossmachine) packages=("${crossmachine_packages[@]}") ;;
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
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
else
  export DEBIAN_FRONTEND=noninteractive
  # the :arm64 packages need arm64 among dpkg's foreign architectures; apt-get update then reads its indexes
  if [ "$set_name" = crossmachine ] && ! dpkg --print-foreign-architectures | grep -qx arm64; then
    echo "install-deps: adding arm64 to dpkg's architectures (dpkg --add-architecture arm64)"
    "${sudo_cmd[@]}" dpkg --add-architecture arm64
  fi
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Box2D's source, for the builds (the Docker image's build stage copies the script and its patch beside this one)
if [ "$set_name" != runtime ]; then
  fetch=$(dirname "$0")/../third_party/box2d/fetch-source.sh
  [ -f "$fetch" ] || {
    echo "install-deps: $fetch is missing (the repository's third_party/box2d/ must be beside deploy/)" >&2
    exit 1
  }
  "${sudo_cmd[@]}" bash "$fetch"
fi
