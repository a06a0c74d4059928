#!/usr/bin/env bash
# Makes (once) a Debian root holding a newer release's MeshLab, for the tests that run our plugin
# inside that real program: one root per Debian suite named in meshlab-builds.tsv (runs_in).
# Built with debootstrap from the machine's own Debian mirror into the cache folder and kept
# there, so a re-run costs nothing; a root that was left half-made is built again.
#
# usage: scripts/make-meshlab-root.sh SUITE      SUITE: a runs_in suite of meshlab-builds.tsv
#   prints the root's folder; MeshLab then runs as `chroot ROOT meshlab` (see tests/meshlab_roots)
#   SDP_CACHE_DIR      cache folder (default: ~/.cache/straightest-param); roots in roots/SUITE
#   SDP_DEBIAN_MIRROR  Debian mirror (default: the first one in the machine's apt sources)
# Needs root (debootstrap, chroot).
set -euo pipefail

source "$(dirname "${BASH_SOURCE[0]}")/meshlab-builds.sh"
suites=$(meshlab_root_suites | paste -sd'|')
if [[ $# -ne 1 ]] || ! meshlab_root_suites | grep -qx -- "$1"; then
  echo "usage: $0 $suites" >&2
  exit 2
fi
suite=$1
cache_dir="${SDP_CACHE_DIR:-$HOME/.cache/straightest-param}"
root="$cache_dir/roots/$suite"

# MeshLab's own plugins need these libraries, which the package only recommends: without them
# the GUI opens a modal "Error while loading plugins" dialog. mesa for software OpenGL under Xvfb.
packages=(meshlab lib3ds-1-3 libgomp1 libmuparser2v5 libopenctm1 libqhull-r8.0 libgl1-mesa-dri)
# What this suite's MeshLab needs beyond that (the table's root_extras).
extras=$(meshlab_builds | awk -F'\t' -v suite="$suite" '$5 == suite && $9 != "-" { print $9 }' | tr ',' '\n' | sort -u)
for extra in $extras; do packages+=("$extra"); done
# The marker records what the root was made with: a change of the list rebuilds it.
marker_text="sdp-root $suite ${packages[*]}"

if [[ -f "$root/.sdp-root-ready" && "$(cat "$root/.sdp-root-ready")" == "$marker_text" ]]; then
  echo "$root"
  exit 0
fi
if [[ $(id -u) -ne 0 ]]; then
  echo "make-meshlab-root: building the $suite root needs root (debootstrap, chroot)" >&2
  exit 1
fi
if ! command -v debootstrap >/dev/null; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends debootstrap >&2 ||
    { apt-get update >&2 && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends debootstrap >&2; }
fi

source "$(dirname "${BASH_SOURCE[0]}")/debian-mirror.sh"
mirror="${SDP_DEBIAN_MIRROR:-$(machine_mirror)}"
mirror=${mirror:-http://deb.debian.org/debian}
mirror=${mirror%/}

started=$SECONDS
part="$root.part"
cleanup() {
  # Never leave the host's /proc mounted inside a root that is about to be removed.
  umount "$part/proc" 2>/dev/null || true
}
trap cleanup EXIT
cleanup
rm -rf "$part"
mkdir -p "$(dirname "$root")"
echo "make-meshlab-root: debootstrap $suite from $mirror (a few minutes, about 220 MB)" >&2
debootstrap --variant=minbase "$suite" "$part" "$mirror" >"$cache_dir/roots/$suite.debootstrap.log" 2>&1 ||
  { tail -20 "$cache_dir/roots/$suite.debootstrap.log" >&2; exit 1; }
mount -t proc proc "$part/proc"
cp /etc/resolv.conf "$part/etc/resolv.conf" 2>/dev/null || true
# The mirror's sid is a dated snapshot whose Release file has expired.
chroot "$part" apt-get -o Acquire::Check-Valid-Until=false update >&2
chroot "$part" env DEBIAN_FRONTEND=noninteractive \
  apt-get install -y --no-install-recommends "${packages[@]}" >&2
chroot "$part" apt-get clean
chroot "$part" dpkg-query -W -f='${Version}\n' meshlab >"$part/.sdp-meshlab-version"
umount "$part/proc"
echo "$marker_text" >"$part/.sdp-root-ready"
rm -rf "$root"
mv "$part" "$root"
echo "make-meshlab-root: $suite root ready (MeshLab $(cat "$root/.sdp-meshlab-version")) in $((SECONDS - started)) s" >&2
echo "$root"
