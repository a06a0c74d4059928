#!/usr/bin/env bash
# Downloads Debian's upstream MeshLab tarball of each source version in meshlab-builds.tsv (they carry
# src/common and a full vcglib: the plugin headers no -dev package ships), checks their SHA256,
# extracts each once and records the source folder in $SDP_CACHE_DIR/meshlab-<version>.path for
# cmake/plugins.cmake.
# Safe to re-run: a verified tarball is not downloaded again, an extracted tree not re-extracted.
#
#   SDP_CACHE_DIR   cache folder (default: ~/.cache/straightest-param)
#   SDP_DEBIAN_MIRROR  Debian mirror to use (default: the first one in the machine's apt sources)
set -euo pipefail

cache_dir="${SDP_CACHE_DIR:-$HOME/.cache/straightest-param}"
mkdir -p "$cache_dir/src"

fallback_mirror="http://deb.debian.org/debian"

# machine_mirror: the mirror in this machine's apt sources.
source "$(dirname "${BASH_SOURCE[0]}")/debian-mirror.sh"
source "$(dirname "${BASH_SOURCE[0]}")/meshlab-builds.sh"

sha256_matches() {  # file hash
  [[ -f "$1" ]] && echo "$2  $1" | sha256sum --check --status
}

download() {  # file hash dest
  local file=$1 hash=$2 dest=$3 mirror
  for mirror in "${SDP_DEBIAN_MIRROR:-$(machine_mirror)}" "$fallback_mirror"; do
    [[ -n "$mirror" ]] || continue
    echo "fetch-meshlab-sources: downloading $mirror/pool/main/m/meshlab/$file" >&2
    rm -f "$dest.part"
    # apt-helper checks the hash itself and leaves no file when it does not match.
    if /usr/lib/apt/apt-helper download-file "$mirror/pool/main/m/meshlab/$file" "$dest.part" \
      "SHA256:$hash" >&2 && sha256_matches "$dest.part" "$hash"; then
      mv "$dest.part" "$dest"
      return 0
    fi
    # A snapshot or partial mirror may not carry the unstable pool: try the next one.
  done
  echo "fetch-meshlab-sources: could not download $file" >&2
  return 1
}

# One tarball per version (builds of one version share it), in the table's order.
while IFS=$'\t' read -r version file hash; do
  tarball="$cache_dir/$file"
  path_file="$cache_dir/meshlab-$version.path"

  if [[ -f "$path_file" ]]; then
    recorded=$(cat "$path_file")
    if [[ -d "$recorded/src/common" ]]; then
      echo "$version $recorded"
      continue
    fi
  fi

  sha256_matches "$tarball" "$hash" || download "$file" "$hash" "$tarball"

  # The tarball holds one top folder (meshlab-<commit>); extract it once.
  top=$(tar -tJf "$tarball" | awk -F/ 'NR == 1 { print $1 }')  # awk reads all: no SIGPIPE
  if [[ ! -d "$cache_dir/src/$top/src/common" ]]; then
    echo "fetch-meshlab-sources: extracting $file" >&2
    rm -rf "$cache_dir/src/$top.part"
    mkdir -p "$cache_dir/src/$top.part"
    tar -xJf "$tarball" -C "$cache_dir/src/$top.part"
    rm -rf "$cache_dir/src/$top"
    mv "$cache_dir/src/$top.part/$top" "$cache_dir/src/$top"
    rmdir "$cache_dir/src/$top.part"
  fi
  echo "$cache_dir/src/$top" >"$path_file"
  echo "$version $cache_dir/src/$top"
done < <(meshlab_builds | awk -F'\t' '!seen[$11]++ { print $11 "\t" $6 "\t" $7 }')
