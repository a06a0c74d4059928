#!/usr/bin/env bash
# Makes a private MeshLab 2020.09 prefix that loads our plugin without root and without touching
# system folders. Debian's meshlab/meshlabserver load plugins only from
# <dir of the binary>/../lib/x86_64-linux-gnu/meshlab/plugins and find libmeshlab-common.so via
# RUNPATH $ORIGIN/../lib/x86_64-linux-gnu/meshlab, so the prefix holds copies of the two binaries
# (a symlink would resolve back to /usr/bin) and symlinks to the system libraries, plugins and
# shaders, plus a symlink to our plugin (a rebuild is picked up without re-running this).
#
# usage: scripts/make-meshlab-prefix.sh PREFIX PLUGIN.so
#   then: xvfb-run -a PREFIX/bin/meshlabserver -i in.off -o out.obj -m wt -s script.mlx
#         PREFIX/bin/meshlab in.off
set -euo pipefail

if [[ $# -ne 2 ]]; then
  echo "usage: $0 PREFIX PLUGIN.so" >&2
  exit 2
fi
prefix=$1
plugin=$(realpath "$2")
system_libdir=/usr/lib/x86_64-linux-gnu/meshlab
libdir=$prefix/lib/x86_64-linux-gnu/meshlab

for binary in /usr/bin/meshlabserver /usr/bin/meshlab "$system_libdir/libmeshlab-common.so"; do
  [[ -e "$binary" ]] || { echo "make-meshlab-prefix: $binary missing (Debian package meshlab)" >&2; exit 1; }
done
[[ -f "$plugin" ]] || { echo "make-meshlab-prefix: $plugin missing (build the plugin first)" >&2; exit 1; }

mkdir -p "$prefix/bin" "$libdir/plugins" "$prefix/share"
for binary in meshlabserver meshlab; do
  # Copy only when changed, so re-running keeps the prefix as is.
  cmp -s "/usr/bin/$binary" "$prefix/bin/$binary" || cp -f "/usr/bin/$binary" "$prefix/bin/$binary"
done
for lib in "$system_libdir"/*.so*; do
  ln -sfn "$lib" "$libdir/$(basename "$lib")"
done
for system_plugin in "$system_libdir"/plugins/*.so; do
  [[ "$(basename "$system_plugin")" == "$(basename "$plugin")" ]] && continue  # ours wins
  ln -sfn "$system_plugin" "$libdir/plugins/$(basename "$system_plugin")"
done
ln -sfn "$plugin" "$libdir/plugins/$(basename "$plugin")"
ln -sfn /usr/share/meshlab "$prefix/share/meshlab"
echo "$prefix"
