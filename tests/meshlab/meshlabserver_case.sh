#!/usr/bin/env bash
# One meshlabserver (MeshLab 2020.09) run of resources/straightest_param.mlx under Xvfb, with the
# plugin from a private prefix (scripts/make-meshlab-prefix.sh), and its check.
#
# usage: meshlabserver_case.sh PREFIX MLX MESH WORKDIR BOUNDARY expect-success|expect-failure PYTHON
#                               [STRETCH_ITERATIONS [MAX_L2]]
#   expect-success: exit 0, OBJ with per-wedge UVs, 0 flipped faces recomputed from the file,
#                   the .mtl texture exists, L2 in the log = L2 of the file (check_obj_uv.py)
#   expect-failure: non-zero exit, no output file, and the reason printed: our filter's log
#                   line "Parametrization: Straightest Distances: <reason>", or MeshLab's own
#                   loader refusing a file it cannot read.
set -uo pipefail

prefix=$1 mlx=$2 mesh=$3 workdir=$4 boundary=$5 expect=$6 python=$7 stretch=${8:-0} max_l2=${9:-}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

rm -rf "$workdir"
mkdir -p "$workdir"
# The filter writes its texture next to the input mesh: work on a copy, never in the shared folder.
cp "$mesh" "$workdir/"
input="$workdir/$(basename "$mesh")"
output="$workdir/out.obj"
script="$workdir/script.mlx"
log="$workdir/meshlabserver.log"
sed "s/name=\"boundary\" value=\"[0-9]*\"/name=\"boundary\" value=\"$boundary\"/" "$mlx" >"$script"
grep -q "name=\"boundary\" value=\"$boundary\"" "$script" || { echo "FAIL: cannot set boundary"; exit 1; }
sed -i "s/name=\"stretchiterations\" value=\"[0-9]*\"/name=\"stretchiterations\" value=\"$stretch\"/" "$script"
grep -q "name=\"stretchiterations\" value=\"$stretch\"" "$script" ||
  { echo "FAIL: cannot set stretchiterations"; exit 1; }

xvfb-run -a -s "-screen 0 1024x768x24" "$prefix/bin/meshlabserver" \
  -i "$input" -o "$output" -m wt -s "$script" >"$log" 2>&1
status=$?
cat "$log"
echo "meshlabserver exit status: $status"

if [[ "$expect" == expect-success ]]; then
  [[ $status -eq 0 ]] || { echo "FAIL: meshlabserver failed"; exit 1; }
  [[ -f "$output" ]] || { echo "FAIL: no $output"; exit 1; }
  grep -q "Straightest distances:" "$log" || { echo "FAIL: the filter's report is not in the log"; exit 1; }
  exec "$python" "$here/check_obj_uv.py" "$output" --log "$log" ${max_l2:+--max-l2 "$max_l2"}
fi

[[ $status -ne 0 ]] || { echo "FAIL: meshlabserver succeeded on an invalid mesh"; exit 1; }
[[ ! -e "$output" ]] || { echo "FAIL: an output file was written"; exit 1; }
if grep -Eq "Parametrization: Straightest Distances: .+" "$log"; then
  echo "PASS: reason: $(grep -Eo 'Parametrization: Straightest Distances: .+' "$log" | head -n1)"
elif grep -q "Failed loading" "$log"; then
  echo "PASS: MeshLab's loader refused the file before the filter ran"
else
  echo "FAIL: no reason in the output"
  exit 1
fi
