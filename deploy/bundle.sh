#!/usr/bin/env bash
# Writes POET as one archive for x86-64 Linux machines where nothing can be installed: the binaries the image
# ships (deploy/Dockerfile), every shared library they load except the C library's, the presets and the shipped
# walkers and environments, under poet-VERSION/{bin,lib,configs,data}. Unpacked anywhere, the binaries find
# their libraries through $ORIGIN; the machine needs only a glibc at least as new as the one the bundle's README
# names.
#   bash deploy/bundle.sh BUILD_DIR OUT.tar.gz     e.g. bash deploy/bundle.sh build poet.tar.gz
# BUILD_DIR is a build tree (deploy/build.sh makes build/); patchelf must be installed (deploy/install-deps.sh).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

help() { sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'; }
usage_error() {
  echo "bundle.sh: $*" >&2
  echo "usage: bash deploy/bundle.sh BUILD_DIR OUT.tar.gz   (--help says more)" >&2
  exit 2
}
die() {
  echo "bundle.sh: $*" >&2
  exit 1
}

case "${1:-}" in -h | --help) help && exit 0 ;; esac
[ $# -eq 2 ] || usage_error "expected two arguments, BUILD_DIR and OUT.tar.gz"
build_dir=$1
out=$2
[ -d "$build_dir" ] || usage_error "$build_dir is not a directory (the build tree)"
[[ $out == *.tar.gz ]] || usage_error "$out: the archive's name must end in .tar.gz"
[ -d "$(dirname "$out")" ] || usage_error "$(dirname "$out"), the archive's directory, does not exist"
[ ! -d "$out" ] || usage_error "$out is a directory"
for tool in patchelf ldd objdump tar gzip; do
  command -v "$tool" >/dev/null || die "$tool is not installed (deploy/install-deps.sh installs it)"
done

# the executables deploy/Dockerfile puts on PATH, by their place in the build tree; poet-coordinator finds
# poet-worker beside it (--local-workers)
binaries=(
  coordinator/poet-coordinator worker/poet-worker
  tools/poetctl tools/poet-lineage tools/poet-report tools/poet-curves tools/poet-controls tools/poet-reference
  tools/poet-rollout tools/poet-eval tools/poet-fidelity
)
for b in "${binaries[@]}"; do
  [ -x "$build_dir/$b" ] || usage_error "$build_dir/$b is missing: $build_dir is not a complete build tree"
done

# The C library stays the machine's: the kernel starts every binary through the machine's loader (its fixed
# path /lib64/ld-linux-x86-64.so.2), and glibc's objects below must come from that loader's very build (they share
# private interfaces), so a bundled copy could not be loaded beside it; the machine's glibc also holds its own
# configuration (users, DNS, locales). Hence the bundle needs a glibc at least as new as its symbols ask for.
# libstdc++ and libgcc_s are GCC's, not glibc's: they are bundled.
glibc_family='^(ld-linux-x86-64\.so\.2|libnsl\.so\.1|libc_malloc_debug\.so\.0|'
glibc_family+='lib(c|m|mvec|pthread|dl|rt|resolv|util|anl|BrokenLocale|thread_db)\.so\.[0-9]+)$'

stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
version=$("$build_dir/coordinator/poet-coordinator" --fingerprint | sed -n 's/^poet: //p')
[ -n "$version" ] || die "$build_dir/coordinator/poet-coordinator --fingerprint names no version"
describe=$(git -C "$root" describe --always --dirty 2>/dev/null || true)
name="poet-$version${describe:+-$describe}"
dir="$stage/$name"
mkdir -p "$dir/bin" "$dir/lib" "$dir/configs" "$dir/data"

# the libraries: ldd gives each binary's whole closure as the loader resolves it here, under its soname
declare -A libraries=()
for b in "${binaries[@]}"; do
  cp "$build_dir/$b" "$dir/bin/"
  listing=$(ldd "$build_dir/$b") || die "ldd $build_dir/$b failed"
  if grep -q 'not found' <<<"$listing"; then
    die "$build_dir/$b: libraries not found on this machine:"$'\n'"$(grep 'not found' <<<"$listing")"
  fi
  while read -r soname path; do
    [[ $soname =~ $glibc_family ]] || libraries[$soname]=$path
  done < <(awk '$2 == "=>" && $3 ~ /^\// { print $1, $3 }' <<<"$listing")
done
for soname in "${!libraries[@]}"; do
  cp -L "${libraries[$soname]}" "$dir/lib/$soname"
  chmod 0644 "$dir/lib/$soname"
done

# DT_RPATH rather than RUNPATH: it comes before LD_LIBRARY_PATH and the loader's cache, and a binary's RPATH also
# serves its libraries' own dependencies (RUNPATH serves only the object's direct ones); $ORIGIN on each library
# keeps that true for the libraries' dlopen too
# shellcheck disable=SC2016  # the loader expands $ORIGIN (the object's directory), not the shell
origin='$ORIGIN'
for f in "$dir"/bin/*; do patchelf --force-rpath --set-rpath "$origin/../lib" "$f"; done
for f in "$dir"/lib/*; do patchelf --force-rpath --set-rpath "$origin" "$f"; done

# every library each bundled binary loads must now resolve inside lib/, with the environment's path emptied
lib_dir=$(realpath "$dir/lib")
for f in "$dir"/bin/*; do
  listing=$(env -u LD_LIBRARY_PATH -u LD_PRELOAD ldd "$f") || die "ldd of the bundled $(basename "$f") failed"
  strays=$(awk '$2 == "=>" { print $1, $3 }' <<<"$listing" | while read -r soname path; do
    [[ $soname =~ $glibc_family || $(realpath -m "$path") == "$lib_dir"/* ]] || echo "  $soname => $path"
  done)
  [ -z "$strays" ] || die "bin/$(basename "$f") would load from the machine:"$'\n'"$strays"
done

# the oldest glibc the bundle runs on: the newest GLIBC_ symbol version any of its objects needs
symbols=$(objdump -T "$dir"/bin/* "$dir"/lib/*)
! grep -q 'GLIBC_PRIVATE' <<<"$symbols" ||
  die "a bundled object uses GLIBC_PRIVATE symbols: it would run only beside this machine's very glibc"
glibc=$(grep -o 'GLIBC_[0-9][0-9.]*' <<<"$symbols" | sed 's/^GLIBC_//' | sort -uV | tail -1)
[ -n "$glibc" ] || die "no GLIBC_ symbol version found in the bundle's objects"
digest=$(env -u LD_LIBRARY_PATH "$dir/bin/poet-coordinator" --fingerprint | sed -n 's/^digest: //p')
[ -n "$digest" ] || die "the bundled poet-coordinator does not run (--fingerprint)"

cp "$root"/deploy/configs/*.textproto "$dir/configs/"
cp -r "$root/data/walkers" "$root/data/environments" "$dir/data/"

# the licences that travel with the binaries: the project's (LICENSE, NOTICE), Box2D's (built into them), and the
# Debian copyright file of each bundled library's package
cp "$root/LICENSE" "$root/NOTICE" "$dir/"
mkdir -p "$dir/licenses"
box2d_source=$(sed -n 's/^POET_BOX2D_SOURCE_DIR:PATH=//p' "$build_dir/CMakeCache.txt")
[ -f "$box2d_source/LICENSE" ] || die "Box2D's LICENSE is not in $box2d_source (POET_BOX2D_SOURCE_DIR of $build_dir)"
cp "$box2d_source/LICENSE" "$dir/licenses/box2d"
for soname in "${!libraries[@]}"; do
  real=$(readlink -f "${libraries[$soname]}")
  package=$(dpkg -S "$real" 2>/dev/null || dpkg -S "${real#/usr}" 2>/dev/null || true)
  package=${package%%:*}
  [ -n "$package" ] && [ -f "/usr/share/doc/$package/copyright" ] || die "no Debian copyright file found for $real"
  cp "/usr/share/doc/$package/copyright" "$dir/licenses/$package"
done
cat >"$dir/README.md" <<EOF
# $name

POET's binaries with the shared libraries they load, for x86-64 Linux: nothing to install.

Needs glibc >= $glibc (\`ldd --version\` prints the machine's). The C library is the machine's own: glibc's
libraries (libc, libm, libpthread, libdl, librt, libresolv, ...) and its loader are not in lib/. Every other
library comes from lib/, found through \$ORIGIN: the directory works wherever it is.

    bin/poet-coordinator --config configs/quick.textproto --run-dir runs/quick \\
        --start-from data/walkers/flat-walker.json --local-workers 2
    bin/poet-coordinator --config configs/paper.textproto --run-dir runs/paper --listen tcp://0.0.0.0:5555 --open-port
    bin/poet-worker --connect tcp://COORDINATOR-HOST:5555       # on each other machine, from its own copy

Build fingerprint digest: $digest. A worker joins only a coordinator with the same digest
(\`bin/poet-worker --fingerprint\`): use copies of this bundle on every machine.
bin/ also holds the tools (poetctl, poet-report, poet-eval, ...; each has --help); configs/ the presets,
data/walkers the shipped walkers, data/environments the shipped courses. Pictures take their fonts from the
machine's fontconfig. Made by deploy/bundle.sh of the POET repository. Licensed under the Apache License 2.0
(LICENSE; NOTICE says what it reimplements); licenses/ holds Box2D's licence and each bundled library's.
EOF

# written beside OUT, then renamed: OUT is never a partial archive
trap 'rm -rf "$stage" "$out.partial"' EXIT
tar --sort=name --owner=0 --group=0 --numeric-owner -C "$stage" -czf "$out.partial" "$name"
mv "$out.partial" "$out"
echo "bundle.sh: wrote $out ($name: ${#binaries[@]} binaries, ${#libraries[@]} libraries," \
  "$(du -h "$out" | cut -f1), needs glibc >= $glibc)"
