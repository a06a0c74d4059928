#!/usr/bin/env bash
# Regenerates the README's MeshLab pictures from a real run of the GUI test
# (tests/gui/meshlab_gui_test.py: Debian's MeshLab 2020.09 under Xvfb, our plugin from a private
# prefix, Filters -> Texture -> Parametrization: Straightest Distances -> Apply):
#   docs/images/meshlab_menu.png      the open Filters -> Texture menu, our entry highlighted
#   docs/images/meshlab_dialog.png    the filter's parameter dialog
#   docs/images/meshlab_textured.png  the MeshLab window after Apply: checkerboard on the mesh,
#                                     our report (L2 stretch, ...) in the log pane
# Fails (and leaves docs/images as it was) if the GUI test fails.
#
# usage: scripts/update-readme-pictures.sh [PLUGIN.so]
#   PLUGIN.so  the 2020.09 plugin; default: SDP_PLUGIN_2020, else built with
#              cmake --build "${SDP_BUILD_DIR:-build}" --target filter_straightest_param_meshlab2020
#   SDP_SHARED_DIR  the shared folder with meshes/ (default: <repo>/../shared)
set -euo pipefail

repo_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir="${SDP_BUILD_DIR:-$repo_dir/build}"
shared_dir="${SDP_SHARED_DIR:-$repo_dir/../shared}"
mesh="$shared_dir/meshes/disk/nefertiti.off"
images="$repo_dir/docs/images"

plugin="${1:-${SDP_PLUGIN_2020:-}}"
if [[ -z "$plugin" ]]; then
  if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
    echo "update-readme-pictures: no build in $build_dir; configure it first" \
         "(cmake -S . -B build) or pass the plugin: $0 PLUGIN.so" >&2
    exit 1
  fi
  cmake --build "$build_dir" --target filter_straightest_param_meshlab2020
  plugin="$build_dir/plugins/meshlab-2020.09/libfilter_straightest_param.so"
fi
[[ -f "$plugin" ]] || { echo "update-readme-pictures: $plugin missing" >&2; exit 1; }
[[ -f "$mesh" ]] || { echo "update-readme-pictures: $mesh missing (set SDP_SHARED_DIR)" >&2; exit 1; }
for tool in convert python3; do
  command -v "$tool" >/dev/null || { echo "update-readme-pictures: $tool missing (scripts/install-deps.sh)" >&2; exit 1; }
done

work=$(mktemp -d "${TMPDIR:-/tmp}/sdp-readme-pictures.XXXXXX")
trap 'rm -rf "$work"' EXIT
out="$work/gui"

python3 "$repo_dir/tests/gui/meshlab_gui_test.py" --plugin "$plugin" --mesh "$mesh" \
  --out "$out" --prefix "$work/prefix"

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

mkdir -p "$images"
crop() {  # crop SRC BOX DEST: no metadata (no dates), so an unchanged picture stays byte-identical
  convert "$1" -crop "$2" +repage -strip -define png:exclude-chunks=date,time "$3.tmp.png"
  mv "$3.tmp.png" "$3"
}
crop "$out/02_menu.png" "$menu_box" "$images/meshlab_menu.png"
crop "$out/03_dialog.png" "$dialog_box" "$images/meshlab_dialog.png"
crop "$out/04_textured.png" "$screen_box" "$images/meshlab_textured.png"
for picture in meshlab_menu meshlab_dialog meshlab_textured; do
  echo "$images/$picture.png: $(identify -format '%wx%h' "$images/$picture.png")"
done
