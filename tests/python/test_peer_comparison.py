"""Side by side with pymeshlab's own parameterizations, in the same process, on the same
meshes, with the same metric (docs/method.md section 5, recomputed here in numpy for every method):
  - ours: straightest-distance weights with the measured, circle and square boundaries
  - harmonic: compute_texcoord_parametrization_harmonic (libigl, cotangent, circle boundary)
  - LSCM: compute_texcoord_parametrization_least_squares_conformal_maps (free boundary)
Writes peers.csv and peers.md into SDP_REPORT_DIR and prints the table. Only our rows are
asserted (one-to-one); the peers' numbers are what they are."""
import csv
import math
import shutil
import time

import pytest

import stretch
from conftest import BOUNDARIES, DISK_MESHES, FILTER, REPORT_DIR

COLUMNS = ["mesh", "faces", "method", "L2", "Linf", "flipped", "seconds", "core_seconds"]


def measure(ml, mesh_path, folder, method):
    copy = folder / mesh_path.name
    if not copy.exists():
        shutil.copy(mesh_path, copy)
    ms = ml.MeshSet()
    ms.load_new_mesh(str(copy))
    start = time.perf_counter()
    try:
        core_seconds = None
        if method.startswith("straightest"):
            boundary = method.split("/", 1)[1]
            core_seconds = getattr(ms, FILTER)(boundary=BOUNDARIES[boundary])["seconds"]
        elif method == "harmonic":
            ms.compute_texcoord_parametrization_harmonic()
        elif method == "lscm":
            ms.compute_texcoord_parametrization_least_squares_conformal_maps()
    except ml.PyMeshLabException as e:
        return {"L2": math.nan, "Linf": math.nan, "flipped": None,
                "seconds": time.perf_counter() - start, "core_seconds": None,
                "error": str(e).split("Details:", 1)[-1].strip()}
    seconds = time.perf_counter() - start  # wall time of the filter call, same for every method
    mesh = ms.current_mesh()
    uv = stretch.wedge_uv_corners(mesh) if method.startswith("straightest") else \
        stretch.vertex_uv_corners(mesh)
    l2, linf = stretch.sander_stretch(stretch.corner_positions(mesh), uv)
    return {"L2": l2, "Linf": linf, "flipped": stretch.folded_faces(uv), "seconds": seconds,
            "core_seconds": core_seconds, "error": ""}


def test_peer_comparison_table(ml, tmp_path, capsys):
    methods = [f"straightest/{b}" for b in BOUNDARIES] + ["harmonic", "lscm"]
    rows = []
    for mesh_path in DISK_MESHES:
        folder = tmp_path / mesh_path.stem
        folder.mkdir()
        faces = None
        for method in methods:
            result = measure(ml, mesh_path, folder, method)
            if faces is None:
                ms = ml.MeshSet()
                ms.load_new_mesh(str(folder / mesh_path.name))
                faces = ms.current_mesh().face_number()
            rows.append({"mesh": mesh_path.stem, "faces": faces, "method": method, **result})

    REPORT_DIR.mkdir(parents=True, exist_ok=True)
    with open(REPORT_DIR / "peers.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS + ["error"])
        writer.writeheader()
        writer.writerows(rows)

    def cell(row, key):
        value = row[key]
        if key in ("L2", "Linf"):
            return "failed" if math.isnan(value) else f"{value:.4f}"
        if key in ("seconds", "core_seconds") and value is not None:
            return f"{value:.3f}"
        return "-" if value is None else str(value)

    lines = ["| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(cell(row, key) for key in COLUMNS) + " |" for row in rows]
    notes = [
        "",
        "Sander L2 / L-infinity stretch normalized so 1.0 is isometric, recomputed in numpy from "
        "the UVs pymeshlab returns; flipped = faces against the map's majority orientation or "
        "degenerate; seconds = wall time of the filter call in pymeshlab 2025.7 (ours includes "
        "writing the 1024x1024 checkerboard PNG); core_seconds = our report's `seconds` (the "
        "parameterization alone).",
    ]
    notes += [f"- {row['mesh']} {row['method']}: {row['error']}" for row in rows if row["error"]]
    (REPORT_DIR / "peers.md").write_text("\n".join(lines + notes) + "\n")
    with capsys.disabled():
        print("\n" + "\n".join(lines + notes))
        print(f"written: {REPORT_DIR / 'peers.md'}, {REPORT_DIR / 'peers.csv'}")

    ours = [row for row in rows if row["method"].startswith("straightest")]
    assert all(row["flipped"] == 0 for row in ours), [r for r in ours if r["flipped"] != 0]
