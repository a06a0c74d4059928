#!/usr/bin/env bash
# Builds the pip package for pymeshlab users, pymeshlab_straightest-<version>-py3-none-linux_x86_64.whl,
# from python/ and the built pymeshlab plugin (build/plugins/meshlab-2025.07, MeshLab 2025.07
# double precision, linked to pymeshlab 2025.7.post1's own libmeshlab-common.so).
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
plugin="$build_dir/plugins/meshlab-2025.07/libfilter_straightest_param.so"
[[ -f "$plugin" ]] || { echo "make-wheel: $plugin missing (cmake --build $build_dir)" >&2; exit 1; }
version=$(sed -n 's/^project(straightest_param VERSION \([0-9.]*\).*/\1/p' "$repo_dir/CMakeLists.txt")

work=$(mktemp -d "${TMPDIR:-/tmp}/sdp-wheel.XXXXXX")
trap 'rm -rf "$work"' EXIT
cp -r "$repo_dir/python" "$work/src"
rm -rf "$work/src/build" "$work/src"/*.egg-info
install -m 644 "$plugin" "$work/src/pymeshlab_straightest/libfilter_straightest_param.so"
echo "VERSION = \"$version\"" >"$work/src/pymeshlab_straightest/_version.py"
mkdir -p "$out_dir"
rm -f "$out_dir"/pymeshlab_straightest-*.whl
"$python" -m pip wheel --disable-pip-version-check --no-deps -q -w "$out_dir" "$work/src"
ls "$out_dir"/pymeshlab_straightest-*.whl
