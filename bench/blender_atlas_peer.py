#!/usr/bin/env python3
"""Blender's atlas as a benchmark peer, through the `bpy` module (pip `bpy` 5.0.1, Blender 5.0.1;
GPL, so bench only: bench/run.sh installs it into .venv-blender, never the product).

usage: blender_atlas_peer.py MESH.off OUT.obj TEXTURE_SIZE GUTTER
What a Blender user does for a whole model: Smart UV Project (its charts), seams from those
islands, Unwrap with *Minimum Stretch* (SLIM, 10 iterations) inside them, then Pack Islands with
the exact shape, rotations, and a margin of GUTTER / TEXTURE_SIZE of the UV square (so that the
gutter compares with the other tools' texels). Writes OUT.obj with the input's vertices and
Blender's per-corner UVs; prints one JSON object: seconds (the three UV steps alone)."""
import json
import sys
import time

import bpy

from blender_peer import edit_all_faces, read_off  # the disk peer's set-up, shared


def main():
    mesh_path, out_path, size, gutter = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    V, F = read_off(mesh_path)
    mesh = edit_all_faces(V, F, "model")
    margin = gutter / size
    start = time.perf_counter()
    bpy.ops.uv.smart_project(island_margin=margin)
    bpy.ops.uv.select_all(action="SELECT")
    bpy.ops.uv.seams_from_islands()
    bpy.ops.uv.unwrap(method="MINIMUM_STRETCH", iterations=10, margin=margin)
    bpy.ops.uv.select_all(action="SELECT")
    bpy.ops.uv.pack_islands(rotate=True, shape_method="CONCAVE", margin_method="FRACTION",
                            margin=margin)
    seconds = time.perf_counter() - start
    bpy.ops.object.mode_set(mode="OBJECT")

    uv_layer = mesh.uv_layers.active.data
    with open(out_path, "w") as out:
        out.write("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V))
        for loop in mesh.loops:
            u, v = uv_layer[loop.index].uv
            out.write(f"vt {u!r} {v!r}\n")
        for poly in mesh.polygons:
            corners = " ".join(f"{mesh.loops[i].vertex_index + 1}/{i + 1}"
                               for i in poly.loop_indices)
            out.write(f"f {corners}\n")
    print(json.dumps({"seconds": seconds}))


if __name__ == "__main__":
    main()
