#!/usr/bin/env bash
# Builds one Debian package per MeshLab build of meshlab-builds.tsv that names one (its deb
# column), from an existing build (cmake --build build), with dpkg-deb:
#   straightest-param-<deb>_<version>_amd64.deb   for that row's MeshLab (users_get_it)
# Each depends on its exact MeshLab version (any Debian revision of it) and installs
#   /usr/lib/x86_64-linux-gnu/meshlab/plugins/libfilter_straightest_param.so   the plugin
#   /usr/bin/straightest_param                                                 the command line tool
#   /usr/share/straightest_param/straightest_param.mlx                         the example script
#   /usr/share/doc/<package>/                                                  README.md, copyright
#   /usr/share/doc/<package>/docs/                                             docs/*.md, docs/images/
#   /usr/share/doc/<package>/bench/results/, tests/robustness/                what the docs link to
# (the docs keep the repository's folders, so that their links resolve where they are).
# They ship the same /usr/bin/straightest_param, so they conflict with one another (a
# system has one MeshLab). Tested by tests/packages/deb_test.py: apt-get install, a run in that
# MeshLab, apt-get remove.
#
# usage: scripts/make-debs.sh [BUILD_DIR [OUT_DIR]]   (defaults: build, BUILD_DIR/debs)
set -euo pipefail

repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=$(realpath "${1:-$repo_dir/build}")
out_dir=$(realpath -m "${2:-$build_dir/debs}")
version=$(sed -n 's/^project(straightest_param VERSION \([0-9.]*\).*/\1/p' "$repo_dir/CMakeLists.txt")
[[ -n "$version" ]] || { echo "make-debs: no project version in CMakeLists.txt" >&2; exit 1; }
cli="$build_dir/bin/straightest_param"
[[ -x "$cli" ]] || { echo "make-debs: $cli missing (cmake --build $build_dir)" >&2; exit 1; }
for tool in dpkg-deb dpkg-shlibdeps; do
  command -v "$tool" >/dev/null || { echo "make-debs: $tool missing (package dpkg-dev)" >&2; exit 1; }
done

work=$(mktemp -d "${TMPDIR:-/tmp}/sdp-debs.XXXXXX")
trap 'rm -rf "$work"' EXIT

# The command line tool's library dependencies, by the names every suite of the table shares.
mkdir -p "$work/shlibs/debian"
printf 'Source: straightest-param\n\nPackage: straightest-param\nArchitecture: any\n' \
  >"$work/shlibs/debian/control"
cli_depends=$(cd "$work/shlibs" && dpkg-shlibdeps -O "$cli" 2>/dev/null | sed -n 's/^shlibs:Depends=//p')
[[ -n "$cli_depends" ]] || { echo "make-debs: dpkg-shlibdeps found nothing for $cli" >&2; exit 1; }

# What the docs ship: README.md, docs/*.md and docs/images/*, and every file they link to.
mapfile -t doc_files < <(cd "$repo_dir" && {
  python3 scripts/check-links.py --closure README.md docs/*.md
  find docs/images -type f
} | sort -u)

mkdir -p "$out_dir"
source "$repo_dir/scripts/meshlab-builds.sh"
packaged=$(meshlab_builds | awk -F'\t' '$8 != "-"')
all_packages=$(cut -f8 <<<"$packaged" | sed 's/^/straightest-param-/')
while IFS=$'\t' read -r -u 3 folder meshlab_version _api _scalar _runs_in _tarball _sha256 suffix _extras where _source; do
  package="straightest-param-$suffix"
  plugin="$build_dir/plugins/$folder/libfilter_straightest_param.so"
  [[ -f "$plugin" ]] || { echo "make-debs: $plugin missing (cmake --build $build_dir)" >&2; exit 1; }
  # MeshLab's versions are YYYY.MM: the next month bounds "this version, any Debian revision".
  year=${meshlab_version%.*} month=${meshlab_version#*.}
  next=$(printf '%s.%02d' "$year" $((10#$month + 1)))
  others=$(grep -vx -- "$package" <<<"$all_packages" | paste -sd, | sed 's/,/, /g')

  staging="$work/$package"
  install -D -m 644 "$plugin" "$staging/usr/lib/x86_64-linux-gnu/meshlab/plugins/libfilter_straightest_param.so"
  install -D -m 755 "$cli" "$staging/usr/bin/straightest_param"
  install -D -m 644 "$repo_dir/resources/straightest_param.mlx" "$staging/usr/share/straightest_param/straightest_param.mlx"
  doc="$staging/usr/share/doc/$package"
  # The README, docs/ and every file they link to (bench results, pictures), at the same
  # relative places, so that every link of the installed docs resolves.
  for file in "${doc_files[@]}"; do
    install -D -m 644 "$repo_dir/$file" "$doc/$file"
  done
  cat >"$doc/copyright" <<EOF
Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/
Upstream-Name: straightest-param
Comment: MeshLab filter plugin and command line tool: parameterization of 3D surface patches by
 straightest distances (Lee, Kim, Lee). Built against MeshLab $meshlab_version headers (GPL-3+).

Files: *
Copyright: the straightest-param authors
License: GPL-3+
 This program is free software: you can redistribute it and/or modify it under the terms of the
 GNU General Public License as published by the Free Software Foundation, either version 3 of
 the License, or (at your option) any later version (the licence of MeshLab, which it links).
 On Debian systems the full text is in /usr/share/common-licenses/GPL-3.
EOF
  mkdir -p "$staging/DEBIAN"
  cat >"$staging/DEBIAN/control" <<EOF
Package: $package
Version: $version
Architecture: amd64
Maintainer: straightest-param developers <straightest-param@users.invalid>
Section: graphics
Priority: optional
Depends: meshlab (>= $meshlab_version~), meshlab (<< $next~), $cli_depends
Conflicts: $others
Replaces: $others
Installed-Size: $(du -sk "$staging" | cut -f1)
Description: MeshLab $meshlab_version filter: parameterization by straightest distances
 Flattens a disk-shaped 3D surface patch onto the plane with per-wedge texture coordinates that
 never fold (Filters > Texture > Parametrization: Straightest Distances), with L2/Linf stretch,
 flipped faces and fallbacks reported; also the straightest_param command line tool.
 For MeshLab $meshlab_version: $where.
EOF
  deb="$out_dir/${package}_${version}_amd64.deb"
  dpkg-deb --root-owner-group -Zxz --build "$staging" "$deb" >/dev/null
  echo "$deb"
done 3<<<"$packaged"
