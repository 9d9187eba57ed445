#!/usr/bin/env bash
# Installs the Box2D source the project builds (third_party/box2d/CMakeLists.txt): Debian's source package box2d
# 2.4.1-3 (bookworm), fetched by apt-get source, which checks it against the archive's signed index, and unpacked
# with Debian's patches; then the project's project-trigonometry.patch (Box2D's rotations take the project's sine
# and cosine).
#   fetch-source.sh [DEST]    DEST defaults to /usr/local/src/poet/box2d-2.4.1-3, where CMake looks
# Idempotent: a DEST whose stamp names this package and this patch is left alone (another stamp is replaced).
# Atomic: unpacked in a temporary directory beside DEST, then renamed to DEST. The machine's apt configuration is
# not touched: apt reads a private sources list and keeps that index in the temporary directory. Its deb-src line
# names the first non-security mirror of /etc/apt/sources.list.d/debian.sources or /etc/apt/sources.list, else
# http://deb.debian.org/debian; POET_DEBIAN_MIRROR=URL overrides. Needs apt-get, dpkg-source (dpkg-dev) and
# patch, the network to the archive, and root (deploy/install-deps.sh runs it) or a DEST whose parent you write.
set -euo pipefail

package=box2d
version=2.4.1-3
upstream=${version%-*}
suite=bookworm
here=$(cd "$(dirname "$0")" && pwd)
patch_file=$here/project-trigonometry.patch
stamp_name=.poet-source-stamp

die() {
  echo "fetch-source: $*" >&2
  exit 1
}
case "${1:-}" in
-h | --help)
  sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
  ;;
-*)
  echo "fetch-source: unknown option $1 (usage: fetch-source.sh [DEST])" >&2
  exit 2
  ;;
esac
[ $# -le 1 ] || {
  echo "fetch-source: expected at most one argument, DEST (usage: fetch-source.sh [DEST])" >&2
  exit 2
}
dest=$(realpath -m "${1:-/usr/local/src/poet/$package-$version}")
parent=$(dirname "$dest")

# the stamp: the package's version and the patch's digest, one a line (CMake reads it too)
[ -r "$patch_file" ] || die "$patch_file is missing: it belongs beside this script (the repository's box2d/)"
patch_sha=$(sha256sum "$patch_file" | cut -d' ' -f1)
stamp="$package $version"$'\n'"project-trigonometry.patch sha256 $patch_sha"
current() { [ -f "$dest/$stamp_name" ] && [ "$(cat "$dest/$stamp_name")" = "$stamp" ]; }
if current; then
  echo "fetch-source: $dest already holds $package $version with the project's patch"
  exit 0
fi
# anything else there but an empty directory is not ours to replace
if [ -e "$dest" ] && [ ! -f "$dest/$stamp_name" ] && { [ ! -d "$dest" ] || [ -n "$(ls -A "$dest")" ]; }; then
  die "$dest exists but has no $stamp_name: not made by this script; remove it or give another DEST"
fi

for tool in apt-get dpkg-source patch sha256sum flock; do
  command -v "$tool" >/dev/null ||
    die "$tool is not installed (apt-get install dpkg-dev; deploy/install-deps.sh --build installs it)"
done
{ mkdir -p "$parent" 2>/dev/null && [ -w "$parent" ]; } ||
  die "cannot write $parent: run as root (deploy/install-deps.sh does) or give a DEST whose parent you can write"

# one run at a time for this DEST; the one that waited may find the work done
exec 9>"$parent/.$(basename "$dest").lock"
flock 9
if current; then
  echo "fetch-source: $dest already holds $package $version with the project's patch"
  exit 0
fi
work=$(mktemp -d "$parent/.$(basename "$dest").XXXXXX")
trap 'rm -rf "$work"' EXIT
chmod 0755 "$work" # apt downloads as the user _apt, which must reach its directories

# the deb-src line, from the machine's mirror
mirror=${POET_DEBIAN_MIRROR:-}
if [ -z "$mirror" ] && [ -r /etc/apt/sources.list.d/debian.sources ]; then
  mirror=$(awk '$1 == "URIs:" { for (i = 2; i <= NF; i++) if ($i !~ /security/) { print $i; exit } }' \
    /etc/apt/sources.list.d/debian.sources)
fi
if [ -z "$mirror" ] && [ -r /etc/apt/sources.list ]; then
  # one-line entries: "deb [options] URI suite components"
  mirror=$(awk '$1 == "deb" { for (i = 2; i <= NF; i++) if ($i ~ /^[a-z+]+:\/\//) { uri = $i; break }
                              if (uri !~ /security/) { print uri; exit } uri = "" }' /etc/apt/sources.list)
fi
mirror=${mirror:-http://deb.debian.org/debian}
signed_by=
keyring=/usr/share/keyrings/debian-archive-keyring.gpg
[ -r "$keyring" ] && signed_by="[signed-by=$keyring] "
echo "deb-src $signed_by$mirror $suite main" >"$work/sources.list"
mkdir -p "$work/lists/partial" "$work/download"
id _apt >/dev/null 2>&1 && chown _apt "$work/download"

# apt with the private list and index only; no package cache file written (it would be the system's)
apt_private=(apt-get -q -o "Dir::Etc::SourceList=$work/sources.list" -o Dir::Etc::SourceParts=/dev/null
  -o "Dir::State::Lists=$work/lists" -o Dir::Cache::pkgcache= -o Dir::Cache::srcpkgcache=)
echo "fetch-source: $package $version from $mirror $suite (deb-src)"
if ! "${apt_private[@]}" --error-on=any update >"$work/update.log" 2>&1; then
  cat "$work/update.log" >&2
  die "apt-get update of $mirror $suite's source index failed (above); is the archive reachable?"
fi
if ! (cd "$work/download" && "${apt_private[@]}" source --only-source "$package=$version") \
  >"$work/source.log" 2>&1; then
  cat "$work/source.log" >&2
  die "apt-get source $package=$version failed (above)"
fi
tree=$work/download/$package-$upstream
{ [ -f "$tree/include/box2d/b2_math.h" ] && [ -d "$tree/src" ]; } ||
  die "apt-get source unpacked no $package-$upstream with include/box2d/b2_math.h and src/ in $work/download"
grep -q '^dpkg-source: info: applying' "$work/source.log" ||
  die "dpkg-source applied none of Debian's patches to $package $version:"$'\n'"$(cat "$work/source.log")"

# the project's patch, then the stamp
patch -d "$tree" -p1 --forward --batch --no-backup-if-mismatch --silent <"$patch_file" ||
  die "$patch_file does not apply to $package $version"
grep -q 'b2SinCos(angle, &s, &c)' "$tree/include/box2d/b2_math.h" ||
  die "$patch_file applied, but b2_math.h does not call b2SinCos"
printf '%s\n' "$stamp" >"$tree/$stamp_name"

# into place: an older DEST (another stamp) is moved aside and removed with the temporary directory
[ ! -e "$dest" ] || mv "$dest" "$work/previous"
mv "$tree" "$dest"
echo "fetch-source: installed $package $version (Debian's patches and the project's) in $dest"
