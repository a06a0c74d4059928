#!/usr/bin/env python3
"""Atlas peers for bench/atlas.py, each run in a process of its own (so that its peak memory is
its own): xatlas (pip `xatlas` 0.0.11), Geogram 1.9.3's atlas maker (pip `geotex` 0.1.3) and
MeshLab's own atlas filters through pymeshlab.

usage: atlas_peers.py METHOD MESH.off OUT.obj TEXTURE_SIZE GUTTER
  METHOD  xatlas          default chart and pack options, resolution TEXTURE_SIZE, padding GUTTER
          xatlas-brute    the same with bruteForce packing
          geotex          Geogram's mesh_make_atlas with geotex's defaults (it takes no texture
                          size nor gutter: see run_geotex)
          voronoi         MeshLab *Parametrization: Voronoi Atlas* with its defaults
          trivial         MeshLab *Parametrization: Trivial Per-Triangle*, its defaults except the
                          texture size (the first of TEXTURE_SIZE, 2x, 4x... that it accepts)
Writes OUT.obj (v, vt, f v/vt: the input's vertices where the tool keeps them) and prints one JSON
object: seconds (the tool's own work, not reading or writing files) and what the tool says."""
import json
import sys
import time

import numpy as np


def read_off(path):
    words = open(path).read().split()
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    at = 4
    V = np.array(words[at:at + 3 * nv], dtype=np.float64).reshape(nv, 3)
    at += 3 * nv
    F = np.array(words[at:at + 4 * nf], dtype=np.int64).reshape(nf, 4)
    assert (F[:, 0] == 3).all(), "triangles only"
    return V, F[:, 1:]


def write_obj(path, V, face_v, uv, face_uv):
    with open(path, "w") as out:
        out.write("".join(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in V))
        out.write("".join(f"vt {u:.9g} {v:.9g}\n" for u, v in uv))
        out.write("".join(f"f {a + 1}/{ta + 1} {b + 1}/{tb + 1} {c + 1}/{tc + 1}\n"
                          for (a, b, c), (ta, tb, tc) in zip(face_v, face_uv)))


def run_xatlas(mesh, out, size, gutter, brute):
    import xatlas
    V, F = read_off(mesh)
    start = time.perf_counter()
    atlas = xatlas.Atlas()
    atlas.add_mesh(V.astype(np.float32), F.astype(np.uint32))
    pack = xatlas.PackOptions()
    pack.resolution = size
    pack.padding = gutter
    pack.bruteForce = brute
    atlas.generate(xatlas.ChartOptions(), pack)
    seconds = time.perf_counter() - start
    vmapping, indices, uvs = atlas[0]
    # xatlas's output vertex i is input vertex vmapping[i], so corners keep the input's vertices.
    write_obj(out, V, vmapping[indices], uvs, indices)
    return {"seconds": seconds, "tool_charts": int(atlas.chart_count)}


def run_geotex(mesh, out, size, gutter):
    """Geogram's GEO::mesh_make_atlas through geotex 0.1.3 (Geogram 1.9.3, the atlas maker Meshroom
    uses). geotex exposes one function, make_atlas(vertices float64 (N, 3), faces uint32 (M, 3),
    hard_angles_threshold=45.0, parameterizer="abf" | "lscm" | "spectral_lscm",
    packer="xatlas" | "tetris", verbose=False) -> (3M, 2) float64 UVs, corner k of face f at row
    3f + k, in [0, 1]; all left at their defaults here. It takes no texture size nor gutter:
    Geogram's xatlas packing asks xatlas for a padding of 1 texel at the resolution xatlas picks
    itself, then scales the atlas into the unit square, so `size` and `gutter` are not passed."""
    import ctypes
    import os
    import re
    import tempfile
    import geotex
    V, F = read_off(mesh)
    vertices = np.ascontiguousarray(V, dtype=np.float64)
    faces = np.ascontiguousarray(F, dtype=np.uint32)
    libc = ctypes.CDLL(None)
    said = {}
    # Geogram's logger writes to the C stdout; it goes to a file here, so that the last line of
    # this process's stdout stays the JSON below, and is passed on to stderr.
    sys.stdout.flush()
    saved = os.dup(1)
    with tempfile.TemporaryFile("w+") as log:
        os.dup2(log.fileno(), 1)
        start = time.perf_counter()
        try:
            uv = geotex.make_atlas(vertices, faces)
        except Exception as e:  # geotex raises when Geogram's atlas maker fails
            said["refused"] = f"{type(e).__name__}: {str(e).strip()}"
        seconds = time.perf_counter() - start
        libc.fflush(None)
        os.dup2(saved, 1)
        os.close(saved)
        log.seek(0)
        text = log.read()
    sys.stderr.write(text)
    said["seconds"] = seconds
    if "refused" in said:
        return said
    uv = np.asarray(uv, dtype=np.float64).reshape(-1, 2)
    if uv.shape[0] != 3 * len(F):
        return {"seconds": seconds, "refused": f"{uv.shape[0]} UVs for {len(F)} faces"}
    packed = re.findall(r"Packing (\d+) charts", text)
    if packed:
        said["tool_charts"] = int(packed[-1])
    # The input's vertices and faces kept; corners with the same UV values share one vt.
    unique_uv, face_uv = np.unique(uv, axis=0, return_inverse=True)
    write_obj(out, V, F, unique_uv, face_uv.reshape(-1, 3))
    return said


def run_meshlab(mesh, out, size, method):
    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(mesh)
    said = {}
    start = time.perf_counter()
    if method == "voronoi":
        ms.generate_voronoi_atlas_parametrization()
        # The filter adds layers; the one with wedge texture coordinates is the atlas.
        for i in range(ms.mesh_number()):
            ms.set_current_mesh(ms.mesh_id_list()[i] if hasattr(ms, "mesh_id_list") else i)
            if ms.current_mesh().has_wedge_tex_coord():
                break
    else:
        for attempt in range(6):
            try:
                ms.compute_texcoord_parametrization_triangle_trivial_per_wedge(textdim=size << attempt)
                said["texture_size"] = size << attempt
                break
            except pymeshlab.PyMeshLabException as e:
                said.setdefault("refusals", []).append(f"{size << attempt}: {str(e).strip()}")
        else:
            return {"seconds": time.perf_counter() - start, "refused": said["refusals"][-1]}
    seconds = time.perf_counter() - start
    m = ms.current_mesh()
    V = m.vertex_matrix()
    F = m.face_matrix()
    wedge = m.wedge_tex_coord_matrix()  # 3F x 2, corner k of face f at row 3f + k
    uv, face_uv = np.unique(wedge, axis=0, return_inverse=True)
    write_obj(out, V, F, uv, face_uv.reshape(-1, 3))
    said["seconds"] = seconds
    said["vertices_written"] = int(V.shape[0])
    return said


def main():
    method, mesh, out, size, gutter = sys.argv[1:6]
    size, gutter = int(size), int(gutter)
    if method in ("xatlas", "xatlas-brute"):
        result = run_xatlas(mesh, out, size, gutter, method == "xatlas-brute")
    elif method == "geotex":
        result = run_geotex(mesh, out, size, gutter)
    elif method in ("voronoi", "trivial"):
        result = run_meshlab(mesh, out, size, method)
    else:
        sys.exit(f"unknown method {method}")
    print(json.dumps(result))


if __name__ == "__main__":
    main()
