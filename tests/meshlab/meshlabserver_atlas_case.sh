#!/usr/bin/env bash
# One meshlabserver (MeshLab 2020.09) run of resources/straightest_atlas.mlx under Xvfb, with the
# plugin from a private prefix (scripts/make-meshlab-prefix.sh), and its check.
#
# usage: meshlabserver_atlas_case.sh PREFIX MLX MESH WORKDIR expect-success|expect-failure PYTHON
#   expect-success: exit 0, OBJ with per-wedge UVs in [0,1], no flipped face, the charts and L2 in
#                   the log equal to the file's (check_obj_uv.py --atlas), the texture exists
#   expect-failure: non-zero exit, no output file, the filter's one-line reason in the log
set -uo pipefail

prefix=$1 mlx=$2 mesh=$3 workdir=$4 expect=$5 python=$6
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

rm -rf "$workdir"
mkdir -p "$workdir"
cp "$mesh" "$workdir/"
input="$workdir/$(basename "$mesh")"
output="$workdir/out.obj"
log="$workdir/meshlabserver.log"
# A smaller texture keeps the case quick; the rest as the script ships.
sed 's/name="texturesize" value="[0-9]*"/name="texturesize" value="1024"/' "$mlx" >"$workdir/script.mlx"

xvfb-run -a -s "-screen 0 1024x768x24" "$prefix/bin/meshlabserver" \
  -i "$input" -o "$output" -m wt -s "$workdir/script.mlx" >"$log" 2>&1
status=$?
cat "$log"
echo "meshlabserver exit status: $status"

if [[ "$expect" == expect-success ]]; then
  [[ $status -eq 0 ]] || { echo "FAIL: meshlabserver failed"; exit 1; }
  [[ -f "$output" ]] || { echo "FAIL: no $output"; exit 1; }
  grep -q "Straightest distances atlas:" "$log" || { echo "FAIL: no atlas report in the log"; exit 1; }
  exec "$python" "$here/check_obj_uv.py" "$output" --log "$log" --atlas --max-l2 1.05
fi

[[ $status -ne 0 ]] || { echo "FAIL: meshlabserver succeeded on an invalid mesh"; exit 1; }
[[ ! -e "$output" ]] || { echo "FAIL: an output file was written"; exit 1; }
if grep -Eq "Parametrization: Straightest Distances Atlas: .+" "$log"; then
  echo "PASS: reason: $(grep -Eo 'Parametrization: Straightest Distances Atlas: .+' "$log" | head -n1)"
elif grep -q "Failed loading" "$log"; then
  echo "PASS: MeshLab's loader refused the file before the filter ran"
else
  echo "FAIL: no reason in the output"
  exit 1
fi
