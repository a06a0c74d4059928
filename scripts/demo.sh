#!/usr/bin/env bash
# The demo (README): flattens the paper's Nefertiti with the default pipeline (straightest
# weights, measured boundary) and writes out/nefertiti.obj + .mtl + checkerboard PNG, printing
# the report. Works on a fresh Debian 12 machine: installs what it needs first.
#   usage: scripts/demo.sh [MESH] [extra straightest_param options...]
set -euo pipefail

repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo_dir"
# The paper's Nefertiti ships with the repository (resources/meshes, CC0): no other folder needed.
mesh="${1:-$repo_dir/resources/meshes/disk/nefertiti.off}"
shift || true

# The demo needs only the command line tool: not the Debian roots of the MeshLab GUI tests.
SDP_SKIP_ROOTS=1 bash scripts/install-deps.sh
build_dir="${SDP_BUILD_DIR:-$repo_dir/build}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build_dir" -j"$(nproc)" --target straightest_param

mkdir -p out
name=$(basename "${mesh%.*}")
"$build_dir/bin/straightest_param" "$mesh" "out/$name.obj" --report "out/$name.json" "$@"
echo "demo: wrote out/$name.obj, out/$name.mtl, out/${name}_checker.png and out/$name.json"
