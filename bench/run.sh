#!/usr/bin/env bash
# One command for every benchmark table and plot in docs/benchmarks.md:
#   bash bench/run.sh            quality tables, paper Table 1, scaling (CGAL up to 1.65M vertices),
#                                the defaults against the linear map and SLIM, the same bytes on
#                                every run, the mesh readers against vcglib's, atlases of whole
#                                models against xatlas, Geogram, Blender and MeshLab, and of
#                                generated mechanical parts (~70 min)
#   bash bench/run.sh --quick    small meshes only (a smoke run, a few minutes)
# Results go to bench/results/ (Markdown, CSV, PNG) and into docs/benchmarks.md between bench
# markers (and bench/summary.py's short table into README.md).
set -euo pipefail
repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo_dir"
bash scripts/install-deps.sh
.venv/bin/python -m pip install --disable-pip-version-check -q matplotlib "xatlas==0.0.11" "geotex==0.1.3" "manifold3d==3.5.4"
# Blender as a peer (pip bpy 5.0.1, GPL: bench only, in a venv of its own, never the product's).
if [[ ! -x .venv-blender/bin/python ]]; then /usr/bin/python3 -m venv .venv-blender; fi
.venv-blender/bin/python -m pip install --disable-pip-version-check -q "bpy==5.0.1"
build_dir="${SDP_BUILD_DIR:-$repo_dir/build}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build_dir" -j"$(nproc)" --target sdp_bench sdp_score sdp_atlas_score sdp_cgal_peer straightest_param sdp_reader_bench sdp_png_bench
.venv/bin/python bench/run.py --build-dir "$build_dir" "$@"
# What a user gets by default (refined), against the linear map and SLIM (docs/benchmarks.md,
# *Defaults*).
if [[ "${1:-}" == "--quick" ]]; then
  .venv/bin/python bench/defaults.py --build "$build_dir"
  .venv/bin/python bench/atlas.py --build "$build_dir" --only decimated-knight,bunny
else
  .venv/bin/python bench/defaults.py --build "$build_dir" --scaling --doc docs/benchmarks.md
  # The same bytes quiet, loaded and on one core; the work model against the clock.
  .venv/bin/python bench/determinism.py --build "$build_dir" --doc docs/benchmarks.md
  # Our mesh readers against vcglib's importers (docs/benchmarks.md *Reading mesh files*).
  .venv/bin/python bench/readers.py --build "$build_dir" --doc docs/benchmarks.md
  # Atlases of whole models against xatlas, Blender and MeshLab's own (docs/benchmarks.md).
  .venv/bin/python bench/atlas.py --build "$build_dir" --big --doc docs/benchmarks.md
  # Mechanical parts made by CSG (bench/cad_models.py), against xatlas and Geogram's atlas maker.
  .venv/bin/python bench/atlas.py --build "$build_dir" --cad
  # MeshLab's own texture baking on the atlas (docs/benchmarks.md).
  .venv/bin/python bench/baking.py --build "$build_dir" --doc docs/benchmarks.md
fi
