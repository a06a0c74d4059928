#!/usr/bin/env bash
# Builds the pip package for pymeshlab users, pymeshlab_straightest-<version>-py3-none-linux_x86_64.whl,
# from python/ and the plugin built for each pymeshlab release of meshlab-builds.tsv (2025.7.post1:
# build/plugins/meshlab-2025.07, MeshLab 2025.07 double precision, linked to that pymeshlab's own
# libmeshlab-common.so; and the older releases pipelines pin). The import loads the one built for
# the pymeshlab installed.
# The wheel's build tools (setuptools, wheel) come from PyPI in pip's isolated build environment.
#
# usage: scripts/make-wheel.sh [BUILD_DIR [OUT_DIR]]   (defaults: build, BUILD_DIR/wheels)
#   SDP_PYTHON  the python that runs pip (default: <repo>/.venv/bin/python, else python3)
set -euo pipefail

repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=$(realpath "${1:-$repo_dir/build}")
out_dir=$(realpath -m "${2:-$build_dir/wheels}")
python="${SDP_PYTHON:-$repo_dir/.venv/bin/python}"
[[ -x "$python" ]] || python=$(command -v python3)
version=$(sed -n 's/^project(straightest_param VERSION \([0-9.]*\).*/\1/p' "$repo_dir/CMakeLists.txt")

work=$(mktemp -d "${TMPDIR:-/tmp}/sdp-wheel.XXXXXX")
trap 'rm -rf "$work"' EXIT
cp -r "$repo_dir/python" "$work/src"
rm -rf "$work/src/build" "$work/src"/*.egg-info
# One plugin per pymeshlab release of meshlab-builds.tsv (runs_in pymeshlab: 2025.7.post1; and
# pymeshlab-VERSION), in plugins/<pymeshlab version>/, and the table the import picks from.
source "$repo_dir/scripts/meshlab-builds.sh"
table="$work/src/pymeshlab_straightest/_plugins.py"
echo "# Written by scripts/make-wheel.sh: the plugin built for each pymeshlab release." >"$table"
echo "PLUGINS = {" >>"$table"
while IFS=$'\t' read -r -u 3 folder meshlab_version _api _scalar runs_in _rest; do
  pymeshlab_version=${runs_in#pymeshlab-}
  [[ $runs_in == pymeshlab ]] && pymeshlab_version=2025.7.post1
  plugin="$build_dir/plugins/$folder/libfilter_straightest_param.so"
  [[ -f "$plugin" ]] || { echo "make-wheel: $plugin missing (cmake --build $build_dir)" >&2; exit 1; }
  install -D -m 644 "$plugin" \
    "$work/src/pymeshlab_straightest/plugins/$pymeshlab_version/libfilter_straightest_param.so"
  echo "    \"$pymeshlab_version\": (\"$meshlab_version\", \"plugins/$pymeshlab_version/libfilter_straightest_param.so\")," >>"$table"
done 3< <(meshlab_pymeshlab_builds)
echo "}" >>"$table"
echo "VERSION = \"$version\"" >"$work/src/pymeshlab_straightest/_version.py"
mkdir -p "$out_dir"
rm -f "$out_dir"/pymeshlab_straightest-*.whl
"$python" -m pip wheel --disable-pip-version-check --no-deps -q -w "$out_dir" "$work/src"
ls "$out_dir"/pymeshlab_straightest-*.whl
