#!/usr/bin/env python3
"""Blender's UV unwrap as a benchmark peer, through the `bpy` module (pip `bpy` 5.0.1, Blender
5.0.1; GPL, so bench only: bench/run.sh installs it into .venv-blender, never the product).

usage: blender_peer.py MESH METHOD SCORER      METHOD: slim (Unwrap "Minimum Stretch", 10
                                               iterations) | abf (Unwrap "Angle Based", ABF++)
The disk patch is unwrapped whole with no seam but its own boundary. Blender keeps UVs per face
corner; on a patch with no seam every corner of a vertex gets the same UV, which is checked here
(`corner_spread`, the largest distance between two corners of one vertex, relative to the layout's
size) and then scored per vertex by the project's own metric code (sdp_score). Prints one JSON
object: method, seconds (the unwrap alone, not the file read or the mesh set-up), the scores."""
import json
import pathlib
import subprocess
import sys
import tempfile
import time

import bpy


def read_off(path):
    words = pathlib.Path(path).read_text().split()
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    at = 4
    V = [tuple(float(x) for x in words[at + 3 * i:at + 3 * i + 3]) for i in range(nv)]
    at += 3 * nv
    F = []
    for _ in range(nf):
        k = int(words[at])
        F.append(tuple(int(x) for x in words[at + 1:at + 1 + k]))
        at += 1 + k
    return V, F


def edit_all_faces(V, F, name):
    """A fresh scene holding the mesh (V, F), in Edit Mode with every face selected, as a user
    has it before an unwrap; returns the Blender mesh (vertex and face order kept)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(V, [], F)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    return mesh


def main():
    mesh_path, method, scorer = sys.argv[1], sys.argv[2], sys.argv[3]
    V, F = read_off(mesh_path)
    mesh = edit_all_faces(V, F, "patch")
    start = time.perf_counter()
    if method == "slim":
        bpy.ops.uv.unwrap(method="MINIMUM_STRETCH", iterations=10, margin=0.0, fill_holes=True)
    elif method == "abf":
        bpy.ops.uv.unwrap(method="ANGLE_BASED", margin=0.0, fill_holes=True)
    else:
        sys.exit(f"unknown method {method}")
    seconds = time.perf_counter() - start
    bpy.ops.object.mode_set(mode="OBJECT")

    uv_layer = mesh.uv_layers.active.data
    per_vertex = [None] * len(V)
    spread = 0.0
    for loop in mesh.loops:
        u, v = uv_layer[loop.index].uv
        seen = per_vertex[loop.vertex_index]
        if seen is None:
            per_vertex[loop.vertex_index] = (u, v)
        else:
            spread = max(spread, abs(seen[0] - u), abs(seen[1] - v))
    used = [p for p in per_vertex if p is not None]
    size = max(max(p[0] for p in used) - min(p[0] for p in used),
               max(p[1] for p in used) - min(p[1] for p in used))
    with tempfile.TemporaryDirectory() as folder:
        uv_file = pathlib.Path(folder) / "uv.txt"
        with open(uv_file, "w") as out:
            for p in per_vertex:
                u, v = p if p is not None else (0.0, 0.0)
                out.write(f"{float(u)!r} {float(v)!r}\n")
        done = subprocess.run([scorer, mesh_path, str(uv_file)], capture_output=True, text=True)
    if done.returncode != 0:
        print(json.dumps({"method": f"blender_{method}", "error": done.stderr.strip()}))
        return
    scored = json.loads(done.stdout)
    scored.update({"method": f"blender_{method}", "seconds": seconds,
                   "corner_spread": spread / size if size > 0 else 0.0})
    print(json.dumps(scored))


if __name__ == "__main__":
    main()
