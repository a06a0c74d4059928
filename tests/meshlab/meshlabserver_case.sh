#!/usr/bin/env bash
# One meshlabserver (MeshLab 2020.09) run of one of our filters' .mlx scripts under Xvfb, with the
# plugin from a private prefix (scripts/make-meshlab-prefix.sh), and its check.
#
# usage: meshlabserver_case.sh patch|atlas PREFIX MLX MESH WORKDIR expect-success|expect-failure
#                               PYTHON [NAME=VALUE ...] [--max-l2 L2]
#   patch|atlas:    which filter MLX runs (resources/straightest_param.mlx or
#                   straightest_atlas.mlx): the log lines and checks that belong to it
#   NAME=VALUE:     sets the script's parameter NAME (e.g. boundary=1, stretchiterations=10)
#   expect-success: exit 0, OBJ with per-wedge UVs, 0 flipped faces recomputed from the file,
#                   the .mtl texture exists, L2 (and the atlas's charts) in the log = the file's
#                   (check_obj_uv.py), L2 at most L2 when given
#   expect-failure: non-zero exit, no output file, and the reason printed: our filter's log
#                   line "<filter's name>: <reason>", or MeshLab's own loader refusing a file it
#                   cannot read.
set -uo pipefail

filter=$1 prefix=$2 mlx=$3 mesh=$4 workdir=$5 expect=$6 python=$7
shift 7
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

case "$filter" in
  patch) report_line="Straightest distances:" name="Parametrization: Straightest Distances"
         check=() ;;
  atlas) report_line="Straightest distances atlas:"
         name="Parametrization: Straightest Distances Atlas" check=(--atlas) ;;
  *) echo "FAIL: unknown filter '$filter' (patch or atlas)"; exit 1 ;;
esac

rm -rf "$workdir"
mkdir -p "$workdir"
# The filter writes its texture next to the input mesh: work on a copy, never in the shared folder.
cp "$mesh" "$workdir/"
input="$workdir/$(basename "$mesh")"
output="$workdir/out.obj"
script="$workdir/script.mlx"
log="$workdir/meshlabserver.log"
cp "$mlx" "$script"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --max-l2) check+=(--max-l2 "$2"); shift 2 ;;
    *=*)
      param=${1%%=*} value=${1#*=}
      sed -i "s/name=\"$param\" value=\"[^\"]*\"/name=\"$param\" value=\"$value\"/" "$script"
      grep -q "name=\"$param\" value=\"$value\"" "$script" ||
        { echo "FAIL: cannot set $param in $mlx"; exit 1; }
      shift ;;
    *) echo "FAIL: unknown argument '$1'"; exit 1 ;;
  esac
done

xvfb-run -a -s "-screen 0 1024x768x24" "$prefix/bin/meshlabserver" \
  -i "$input" -o "$output" -m wt -s "$script" >"$log" 2>&1
status=$?
cat "$log"
echo "meshlabserver exit status: $status"

if [[ "$expect" == expect-success ]]; then
  [[ $status -eq 0 ]] || { echo "FAIL: meshlabserver failed"; exit 1; }
  [[ -f "$output" ]] || { echo "FAIL: no $output"; exit 1; }
  grep -q "$report_line" "$log" || { echo "FAIL: the filter's report is not in the log"; exit 1; }
  exec "$python" "$here/check_obj_uv.py" "$output" --log "$log" "${check[@]}"
fi

[[ $status -ne 0 ]] || { echo "FAIL: meshlabserver succeeded on an invalid mesh"; exit 1; }
[[ ! -e "$output" ]] || { echo "FAIL: an output file was written"; exit 1; }
if grep -Eq "$name: .+" "$log"; then
  echo "PASS: reason: $(grep -Eo "$name: .+" "$log" | head -n1)"
elif grep -q "Failed loading" "$log"; then
  echo "PASS: MeshLab's loader refused the file before the filter ran"
else
  echo "FAIL: no reason in the output"
  exit 1
fi
