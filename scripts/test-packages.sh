#!/usr/bin/env bash
# The packages as users install them (a stage of scripts/test.sh, after ctest; it needs the build):
#   1. scripts/make-debs.sh, then tests/packages/deb_test.py for each .deb in the MeshLab of its
#      row of meshlab-builds.tsv: on this machine (host) or in its suite's Debian root
#      (scripts/make-meshlab-root.sh);
#   2. scripts/make-wheel.sh, then tests/packages/wheel_test.py in a fresh virtual environment
#      where only `pip install <wheel>` ran (it brings pymeshlab 2025.7.post1 from PyPI), and in
#      one per older pymeshlab of meshlab-builds.tsv, installed before the wheel.
# Not inside ctest on purpose: the host case installs into this machine's MeshLab for a moment,
# which the meshlabserver and GUI tests (possibly run in parallel by ctest -j) must not see.
#
# usage: scripts/test-packages.sh [BUILD_DIR]
#   SDP_SHARED_DIR  extra meshes (optional); SDP_CACHE_DIR  where the Debian roots are
set -euo pipefail

repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=$(realpath "${1:-$repo_dir/build}")
roots="${SDP_CACHE_DIR:-$HOME/.cache/straightest-param}/roots"
out="$build_dir/test-output/packages"
mesh="$repo_dir/resources/meshes/disk/nefertiti.off"
bad_mesh="$repo_dir/resources/meshes/invalid/two_components.off"
python=/usr/bin/python3
[[ -x "$python" ]] || python=$(command -v python3)
rm -rf "$out"
mkdir -p "$out"

failures=0
run_case() {  # name command...
  local name=$1
  shift
  if "$@" >"$out/$name.log" 2>&1; then
    echo "PASS $name"
  else
    echo "FAIL $name (log: $out/$name.log)"
    tail -30 "$out/$name.log"
    failures=$((failures + 1))
  fi
}

debs=$(bash "$repo_dir/scripts/make-debs.sh" "$build_dir" "$build_dir/debs")
version=$(basename "$(echo "$debs" | head -n1)" | cut -d_ -f2)
source "$repo_dir/scripts/meshlab-builds.sh"
while IFS=$'\t' read -r -u 3 _folder meshlab_version _api _scalar runs_in _tarball _sha256 suffix _rest; do
  [[ $suffix != - ]] || continue
  deb="$build_dir/debs/straightest-param-${suffix}_${version}_amd64.deb"
  if [[ $runs_in == host ]]; then
    run_case "deb_${suffix}_this_machine" "$python" "$repo_dir/tests/packages/deb_test.py" \
      --deb "$deb" --meshlab-version "$meshlab_version" --mesh "$mesh" --bad-mesh "$bad_mesh" \
      --out "$out/deb_$suffix"
  elif [[ "${SDP_SKIP_ROOTS:-0}" != 1 ]]; then
    # The harness tests/meshlab_roots builds for this version (meshlab_harness_YYYYMM).
    run_case "deb_${suffix}_$runs_in" "$python" "$repo_dir/tests/packages/deb_test.py" \
      --deb "$deb" --meshlab-version "$meshlab_version" --mesh "$mesh" --bad-mesh "$bad_mesh" \
      --out "$out/deb_$suffix" --root "$roots/$runs_in" \
      --harness "$build_dir/bin/meshlab_harness_${meshlab_version//./}"
  fi
done 3< <(meshlab_builds)

wheel=$(bash "$repo_dir/scripts/make-wheel.sh" "$build_dir" "$build_dir/wheels")
# What the wheel's platform tag may honestly be (docs/pymeshlab.md).
"$repo_dir/.venv/bin/auditwheel" show "$wheel" 2>&1 | tee "$build_dir/wheels/auditwheel.txt" |
  grep -A1 -E "consistent|constrains" || true
venv="$out/wheel-venv"
run_case wheel_fresh_venv bash -c '
  "$1" -m venv "$2" && "$2/bin/python" -m pip install --disable-pip-version-check -q "$3" &&
  "$2/bin/python" "$4/tests/packages/wheel_test.py" --wheel "$3" --out "$5/wheel" \
    --pymeshlab 2025.7.post1' \
  sh "$python" "$venv" "$wheel" "$repo_dir" "$out"
# Beside each older pymeshlab a pipeline has pinned (installed first, with its row's extras).
while IFS=$'\t' read -r -u 3 _folder _version _api _scalar runs_in _tarball _sha256 _deb extras _rest; do
  [[ $runs_in == pymeshlab-* ]] || continue
  pinned=${runs_in#pymeshlab-}
  requirements="pymeshlab==$pinned"
  [[ $extras == - ]] || requirements="$requirements ${extras//,/ }"
  run_case "wheel_beside_$runs_in" bash -c '
    "$1" -m venv "$2" && "$2/bin/python" -m pip install --disable-pip-version-check -q $6 &&
    "$2/bin/python" -m pip install --disable-pip-version-check -q "$3" &&
    "$2/bin/python" "$4/tests/packages/wheel_test.py" --wheel "$3" --out "$5/wheel-$7" \
      --pymeshlab "$7"' \
    sh "$python" "$out/wheel-venv-$runs_in" "$wheel" "$repo_dir" "$out" "$requirements" "$pinned"
done 3< <(meshlab_pymeshlab_builds)

echo "test-packages: $(( $(ls "$out"/*.log | wc -l) - failures )) cases passed, $failures failed"
[[ $failures -eq 0 ]]
