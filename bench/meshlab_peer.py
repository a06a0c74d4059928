#!/usr/bin/env python3
"""MeshLab's own parameterizations (pymeshlab 2025.7) as benchmark peers, one per process so
its peak memory is its own: Harmonic (libigl, cotangent weights, circle boundary) and LSCM.

usage: meshlab_peer.py MESH harmonic|lscm SCORER
Prints one JSON object: method, seconds (the filter call only), extra_mb (peak resident memory
during the call minus the resident memory before it), plus the scorer's metrics of the per-vertex
UVs (the project's own metric code, sdp_score)."""
import json
import pathlib
import subprocess
import sys
import tempfile
import time


def resident_mb():
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    return -1.0


def peak_mb():
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024.0
    return -1.0


def main():
    mesh, method, scorer = sys.argv[1], sys.argv[2], sys.argv[3]
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(mesh)
    before = resident_mb()
    with open("/proc/self/clear_refs", "w") as f:  # peak from here on
        f.write("5")
    start = time.perf_counter()
    if method == "harmonic":
        ms.compute_texcoord_parametrization_harmonic()
    elif method == "lscm":
        ms.compute_texcoord_parametrization_least_squares_conformal_maps()
    else:
        raise SystemExit(f"unknown method {method}")
    seconds = time.perf_counter() - start
    extra = peak_mb() - before
    uv = ms.current_mesh().vertex_tex_coord_matrix()
    with tempfile.TemporaryDirectory() as folder:
        uv_file = pathlib.Path(folder) / "uv.txt"
        with open(uv_file, "w") as out:
            for u, v in uv:
                out.write(f"{float(u)!r} {float(v)!r}\n")
        scored = json.loads(subprocess.run([scorer, mesh, str(uv_file)], check=True,
                                           capture_output=True, text=True).stdout)
    scored.update({"method": f"meshlab_{method}", "seconds": seconds, "extra_mb": extra})
    print(json.dumps(scored))


if __name__ == "__main__":
    main()
