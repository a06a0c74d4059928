#!/usr/bin/env bash
# Regenerates the MeshLab pictures of README.md and docs/meshlab.md from real runs of the GUI test
# (tests/gui/meshlab_gui_test.py: MeshLab under Xvfb, Filters -> Texture -> Parametrization:
# Straightest Distances -> Apply), for each MeshLab GUI the project is tested in:
#   this machine's MeshLab (the host row of meshlab-builds.tsv), our plugin from a private prefix
#   (README.md shows these):
#     docs/images/meshlab_menu.png      the open Filters -> Texture menu, our entry highlighted
#     docs/images/meshlab_dialog.png    the filter's parameter dialog
#     docs/images/meshlab_textured.png  the MeshLab window after Apply: checkerboard on the mesh,
#                                       our report (L2 stretch, ...) in the log pane
#     docs/images/meshlab_atlas_textured.png  the same after the atlas filter (Straightest
#                                       Distances Atlas) on the shared closed bunny
#   each MeshLab of the table that runs in a Debian root (scripts/make-meshlab-root.sh), our plugin
#   in the per-user plugin folder (docs/meshlab.md shows the menu and textured ones):
#     docs/images/meshlab-<version>_{menu,dialog,textured}.png
# Fails if a GUI test fails; the pictures of the versions before it are already updated.
#
# usage: scripts/update-readme-pictures.sh
#   the plugins are built with cmake --build "${SDP_BUILD_DIR:-build}" first
#   SDP_SHARED_DIR  the shared folder with meshes/ (default: <repo>/../shared)
#   SDP_CACHE_DIR   where the Debian roots are (default: ~/.cache/straightest-param)
set -euo pipefail

repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir="${SDP_BUILD_DIR:-$repo_dir/build}"
shared_dir="${SDP_SHARED_DIR:-$repo_dir/../shared}"
roots="${SDP_CACHE_DIR:-$HOME/.cache/straightest-param}/roots"
mesh="$shared_dir/meshes/disk/nefertiti.off"
atlas_mesh="$shared_dir/meshes/closed/bunny.off"
images="$repo_dir/docs/images"

if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
  echo "update-readme-pictures: no build in $build_dir; configure it first (cmake -S . -B build)" >&2
  exit 1
fi
source "$repo_dir/scripts/meshlab-builds.sh"
# version  plugin folder  where MeshLab runs  picture name prefix: the GUIs of the table.
guis=$(meshlab_builds | awk -F'\t' '$5 == "host" { print $2, $1, "prefix", "meshlab" }'
      meshlab_root_builds | awk -F'\t' '{ print $2, $1, $5, "meshlab-" $2 }')
cmake --build "$build_dir" --target $(awk '{ print "plugin_" $2 }' <<<"$guis")
for needed in "$mesh" "$atlas_mesh"; do
  [[ -f "$needed" ]] || { echo "update-readme-pictures: $needed missing (set SDP_SHARED_DIR)" >&2; exit 1; }
done
for tool in convert identify python3; do
  command -v "$tool" >/dev/null || { echo "update-readme-pictures: $tool missing (scripts/install-deps.sh)" >&2; exit 1; }
done

work=$(mktemp -d "${TMPDIR:-/tmp}/sdp-readme-pictures.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$images"

crop() {  # crop SRC BOX DEST: no metadata (no dates), so an unchanged picture stays byte-identical
  convert "$1" -crop "$2" +repage -strip -define png:exclude-chunks=date,time "$3.tmp.png"
  mv "$3.tmp.png" "$3"
}

while read -r -u 3 version folder where name; do
  plugin="$build_dir/plugins/$folder/libfilter_straightest_param.so"
  out="$work/gui-$version"
  if [[ $where == prefix ]]; then
    runner=(--prefix "$work/prefix")
  else
    runner=(--root "$roots/$where" --meshlab-version "$version")
  fi
  python3 "$repo_dir/tests/gui/meshlab_gui_test.py" --plugin "$plugin" --mesh "$mesh" \
    --out "$out" "${runner[@]}"
  if [[ $where == prefix ]]; then
    # The bunny's checker squares are large: their red grid lines cover under the GUI test's
    # 0.1 % of the view (0.097 % seen), so this run asks for half that.
    python3 "$repo_dir/tests/gui/meshlab_gui_test.py" --plugin "$plugin" --mesh "$atlas_mesh" \
      --filter atlas --min-red 0.05 --out "$out-atlas" "${runner[@]}"
  fi

  # Crop boxes from where the test saw the windows (layout.json, [x, y, w, h] each):
  #   menu:     from the top-left corner to the far corner of the open menus (menu bar included)
  #   dialog:   the dialog window
  #   textured: the whole MeshLab window (3D view, layer panel and log pane)
  read -r menu_box dialog_box screen_box < <(python3 - "$out/layout.json" <<'EOF'
import json, sys
layout = json.load(open(sys.argv[1]))
right = max(x + w for x, y, w, h in layout["menus"])
bottom = max(y + h for x, y, w, h in layout["menus"])
geometry = lambda x, y, w, h: "%dx%d+%d+%d" % (w, h, x, y)
print(geometry(0, 0, right, bottom), geometry(*layout["dialog"]), geometry(*layout["screen"]))
EOF
)
  crop "$out/02_menu.png" "$menu_box" "$images/${name}_menu.png"
  crop "$out/03_dialog.png" "$dialog_box" "$images/${name}_dialog.png"
  crop "$out/04_textured.png" "$screen_box" "$images/${name}_textured.png"
  if [[ -d "$out-atlas" ]]; then
    crop "$out-atlas/04_textured.png" "$screen_box" "$images/${name}_atlas_textured.png"
    echo "$images/${name}_atlas_textured.png: $(identify -format '%wx%h' "$images/${name}_atlas_textured.png")"
  fi
  for picture in menu dialog textured; do
    echo "$images/${name}_$picture.png: $(identify -format '%wx%h' "$images/${name}_$picture.png")"
  done
done 3<<<"$guis"
