#!/usr/bin/env python3
"""libigl's SLIM (Rabinovich et al. 2017, symmetric Dirichlet, free boundary) as a bijective
benchmark peer: started from Tutte's map (uniform weights, boundary on a circle), which is
one-to-one, then `iterations` SLIM iterations (each keeps it fold-free).

usage: slim_peer.py MESH ITERATIONS SCORER
Prints one JSON object: method, seconds (Tutte + SLIM, not the file read), plus the scorer's
metrics of the per-vertex UVs (the project's own metric code, sdp_score)."""
import json
import pathlib
import subprocess
import sys
import tempfile
import time

import igl
import numpy as np
import scipy.sparse
import scipy.sparse.linalg


def tutte(V, F):
    """Uniform-weight convex-combination map with the boundary on the unit circle."""
    boundary = igl.boundary_loop(F)
    on_circle = igl.map_vertices_to_circle(V, boundary)
    n = V.shape[0]
    edges = np.vstack([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    edges = np.unique(np.sort(edges, axis=1), axis=0)
    rows = np.concatenate([edges[:, 0], edges[:, 1]])
    cols = np.concatenate([edges[:, 1], edges[:, 0]])
    A = scipy.sparse.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    L = scipy.sparse.diags(np.asarray(A.sum(axis=1)).ravel()) - A
    fixed = np.zeros(n, dtype=bool)
    fixed[boundary] = True
    free = np.flatnonzero(~fixed)
    uv = np.zeros((n, 2))
    uv[boundary] = on_circle
    rhs = -L[free][:, boundary] @ on_circle
    solve = scipy.sparse.linalg.factorized(L[free][:, free].tocsc())
    uv[free, 0] = solve(rhs[:, 0])
    uv[free, 1] = solve(rhs[:, 1])
    return uv


def main():
    mesh, iterations, scorer = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    V, F = igl.read_triangle_mesh(mesh)
    V = np.asfortranarray(V, dtype=np.float64)
    F = np.asfortranarray(F, dtype=np.int32)
    start = time.perf_counter()
    uv = tutte(V, F)
    data = igl.slim_precompute(V, F, np.asfortranarray(uv), igl.MappingEnergyType.SYMMETRIC_DIRICHLET,
                               np.zeros(0, dtype=np.int32), np.zeros((0, 2)), 0.0)
    uv = igl.slim_solve(data, iterations)
    seconds = time.perf_counter() - start
    with tempfile.TemporaryDirectory() as folder:
        uv_file = pathlib.Path(folder) / "uv.txt"
        with open(uv_file, "w") as out:
            for u, v in uv[:, :2]:
                out.write(f"{float(u)!r} {float(v)!r}\n")
        scored = json.loads(subprocess.run([scorer, mesh, str(uv_file)], check=True,
                                           capture_output=True, text=True).stdout)
    scored.update({"method": f"slim_{iterations}", "seconds": seconds})
    print(json.dumps(scored))


if __name__ == "__main__":
    main()
