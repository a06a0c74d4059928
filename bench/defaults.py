#!/usr/bin/env python3
"""What a user gets by default, measured with the installed command line (build/bin/straightest_param):
the default (refined) map against the paper's linear map (--stretch-iterations 0) on every disk mesh,
beside libigl's SLIM and Blender's Unwrap (Minimum Stretch, and Angle Based: bench/blender_peer.py,
in .venv-blender), and on face.off / lilium.off
subdivided up to 1.65M vertices with --scaling. Flipped faces are
recomputed from the written files (OBJ, and float PLY), not taken from the report.

    python3 bench/defaults.py [--build build] [--shared ../shared] [--scaling]
                              [--doc docs/benchmarks.md]

Writes bench/results/defaults.md and, with --doc, that file's bench:defaults block.
"""
import argparse
import json
import os
import pathlib
import struct
import subprocess
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from run import replace_block  # noqa: E402


def obj_corners(path):
    vt, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("vt "):
                vt.append(tuple(float(x) for x in line.split()[1:3]))
            elif line.startswith("f "):
                faces.append([vt[int(c.split("/")[1]) - 1] for c in line.split()[1:4]])
    return faces


def ply_corners(path):
    """The CLI's binary PLY: scalar vertex properties; per face a uchar-count int list and a
    uchar-count float texcoord list (6 floats)."""
    sizes = {"double": 8, "float": 4, "int": 4, "uchar": 1}
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    vertices = int(next(h for h in header if h.startswith("element vertex")).split()[2])
    faces = int(next(h for h in header if h.startswith("element face")).split()[2])
    vertex_bytes = 0
    in_vertex = False
    for h in header:
        if h.startswith("element"):
            in_vertex = h.startswith("element vertex")
        elif h.startswith("property") and in_vertex:
            vertex_bytes += sizes[h.split()[1]]
    at = end + vertices * vertex_bytes
    out = []
    for _ in range(faces):
        n = data[at]
        at += 1 + 4 * n
        m = data[at]
        uv = struct.unpack_from(f"<{m}f", data, at + 1)
        at += 1 + 4 * m
        out.append([(uv[2 * k], uv[2 * k + 1]) for k in range(3)])
    return out


def flipped(corners):
    bad = 0
    for (s1, t1), (s2, t2), (s3, t3) in corners:
        if (s2 - s1) * (t3 - t1) - (s3 - s1) * (t2 - t1) <= 0:
            bad += 1
    return bad


def run(cli, mesh, folder, extra, fmt):
    out = pathlib.Path(folder) / f"out.{fmt}"
    report = pathlib.Path(folder) / "report.json"
    with tempfile.TemporaryFile() as err:
        child = subprocess.Popen([cli, mesh, out, "--quiet", "--report", report] + extra,
                                 stdout=subprocess.DEVNULL, stderr=err)
        _, status, usage = os.wait4(child.pid, 0)  # this run's own peak memory
        child.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        message = err.read().decode(errors="replace").strip()
    if child.returncode != 0:
        return {"error": message}
    r = json.loads(report.read_text())
    r["peak_mb"] = usage.ru_maxrss / 1024
    r["file_flips"] = flipped(obj_corners(out) if fmt == "obj" else ply_corners(out))
    return r


def measure(cli, mesh, fmt):
    with tempfile.TemporaryDirectory() as folder:
        linear = run(cli, mesh, folder, ["--stretch-iterations", "0"], fmt)
        default = run(cli, mesh, folder, [], fmt)
    return linear, default


# A peer still running after this many seconds is stopped, and its cell says so (Blender's
# Minimum Stretch was stopped by hand after 25 minutes on face s2; SLIM took 21 there).
PEER_LIMIT = 1500


def run_peer(command):
    """A peer's process and the JSON its last line prints; None when it fails,
    {"stopped_after": s} when it hits PEER_LIMIT."""
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=PEER_LIMIT)
    except subprocess.TimeoutExpired:
        return {"stopped_after": PEER_LIMIT}
    if done.returncode != 0:
        return None
    return json.loads(done.stdout.strip().splitlines()[-1])


def slim(build, mesh, iterations=20):
    """libigl SLIM from Tutte (bench/slim_peer.py), in its own process."""
    return run_peer([sys.executable, pathlib.Path(__file__).resolve().parent / "slim_peer.py",
                     mesh, str(iterations), build / "bin" / "sdp_score"])


BLENDER_PYTHON = pathlib.Path(__file__).resolve().parent.parent / ".venv-blender" / "bin" / "python"


def blender(build, mesh, method):
    """Blender's Unwrap (bench/blender_peer.py, pip bpy in .venv-blender), in its own process;
    None when bpy is not installed (bench/run.sh installs it)."""
    if not BLENDER_PYTHON.exists():
        return None
    result = run_peer([BLENDER_PYTHON, pathlib.Path(__file__).resolve().parent /
                       "blender_peer.py", mesh, method, build / "bin" / "sdp_score"])
    return None if result is None or "error" in result else result


def peers(build, mesh):
    return {"slim": slim(build, mesh), "blender_slim": blender(build, mesh, "slim"),
            "blender_abf": blender(build, mesh, "abf")}


def no_limit_row(name, linear, default, unlimited):
    """The default beside K = 10 without a work limit (where the Newton steps get to run)."""
    for r in (linear, default, unlimited):
        if "error" in r:
            return f"| {name} | refused: {r['error']} |"
    fb = sum(unlimited["stage_seconds"].get(stage, 0) for stage in ("free_boundary", "newton"))
    return (f"| {name} | {unlimited['vertices']:,} | {default['l2_stretch']:.4f} | "
            f"{default['seconds']:.2f} | {unlimited['l2_stretch_fixed_boundary']:.4f} | "
            f"{unlimited['l2_stretch']:.4f} | {unlimited['free_boundary_steps']} | {fb:.1f} | "
            f"{unlimited['seconds']:.1f} | {unlimited['seconds'] / linear['seconds']:.1f}× | "
            f"{default['peak_mb']:,.0f} / {unlimited['peak_mb']:,.0f} | "
            f"{unlimited['file_flips']} |")


NO_LIMIT_HEADER = (
    "| mesh | vertices | L2, default | s, default | L2 after reweighting, K = 10 | "
    "L2, K = 10 free boundary, no work limit | free-boundary steps | s, free-boundary steps | "
    "s, no work limit | × linear | peak MB, default / no limit | flipped in the file, no limit |\n"
    "|---|---|---|---|---|---|---|---|---|---|---|---|")


PEERS = ("slim", "blender_slim", "blender_abf")


def row(name, linear, default, found=None):
    if "error" in linear or "error" in default:
        return f"| {name} | refused: {linear.get('error') or default.get('error')} |"
    ratio = default["seconds"] / linear["seconds"] if linear["seconds"] > 0 else float("nan")
    found = found or {}
    cells = []
    for key in PEERS:
        peer = found.get(key)
        if peer is None:
            cells.append("–")
        elif "stopped_after" in peer:
            cells.append(f"stopped at {peer['stopped_after']} s")
        else:
            cells.append(f"{peer['l2_stretch']:.4f} ({peer['flipped_faces']} flipped), "
                         f"{peer['seconds']:.2f} s")
    # The best peer that does not fold: the bar the default must stay near.
    good = [found[k]["l2_stretch"] for k in PEERS
            if found.get(k) is not None and "stopped_after" not in found[k]
            and found[k]["flipped_faces"] == 0]
    best = f"{default['l2_stretch'] / min(good):.3f}" if good else "–"
    peer_cells = " | ".join(cells) + f" | {best}"
    return (f"| {name} | {default['vertices']:,} | {linear['l2_stretch']:.4f} | "
            f"{default['l2_stretch']:.4f} | {peer_cells} | {linear['seconds']:.2f} | "
            f"{default['seconds']:.2f} | {ratio:.1f}× | {default['refinement_stop']} | "
            f"{default['storage']['degenerate_faces']} / {default['storage']['moved_vertices']} | "
            f"{linear['file_flips']} / {default['file_flips']} |")


HEADER = ("| mesh | vertices | L2, linear (K = 0) | L2, default | libigl SLIM 20 it. from Tutte | "
          "Blender Minimum Stretch (SLIM, 10 it.) | Blender Angle Based (ABF++) | "
          "default / best non-folding peer L2 | s, linear | s, default | default / linear time | "
          "refinement stopped by | faces repaired as stored / vertices moved | flipped in the "
          "file, linear / default |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    root = pathlib.Path(__file__).resolve().parent.parent
    parser.add_argument("--build", default=root / "build", type=pathlib.Path)
    parser.add_argument("--shared", default=root.parent / "shared", type=pathlib.Path)
    parser.add_argument("--scaling", action="store_true")
    parser.add_argument("--cache", default=pathlib.Path.home() / ".cache/straightest-param/bench",
                        type=pathlib.Path)
    parser.add_argument("--doc", type=pathlib.Path,
                        help="the file holding the bench:defaults block (docs/benchmarks.md)")
    args = parser.parse_args()
    cli = args.build / "bin" / "straightest_param"

    meshes = sorted((args.shared / "meshes" / "disk").glob("*.off"))
    if not meshes:
        meshes = sorted((root / "resources" / "meshes" / "disk").glob("*.off"))
    lines = ["Each front end's default, OBJ output (full precision) from the command line:", "",
             HEADER]
    for mesh in meshes:
        lines.append(row(mesh.stem, *measure(cli, mesh, "obj"), peers(args.build, mesh)))
        print(lines[-1], flush=True)
    if args.scaling:
        args.cache.mkdir(parents=True, exist_ok=True)
        lines += ["", "Subdivided scans, float PLY output (the core repairs what float rounding "
                  "would collapse):", "", HEADER]
        no_limit = []
        for base, k in (("face", 1), ("face", 2), ("lilium", 4), ("face", 3)):
            mesh = args.cache / f"{base}_s{k}.off"
            if not mesh.exists():
                subprocess.run([args.build / "bin" / "sdp_bench",
                                args.shared / "meshes" / "disk" / f"{base}.off", str(k),
                                "--write-off", mesh], check=True, capture_output=True)
            linear, default = measure(cli, mesh, "ply")
            # The peers where they finish in minutes: up to face s2 (414k vertices; SLIM took
            # 295 s at 207k in an earlier run, and all grow faster than linearly).
            found = peers(args.build, mesh) if base == "face" and k <= 2 else None
            lines.append(row(f"{base} s{k}", linear, default, found))
            print(lines[-1], flush=True)
            with tempfile.TemporaryDirectory() as folder:
                unlimited = run(cli, mesh, folder, ["--time-budget", "0"], "ply")
            no_limit.append(no_limit_row(f"{base} s{k}", linear, default, unlimited))
            print(no_limit[-1], flush=True)
        lines += ["", "The same scans without a work limit (`--time-budget 0`, K = 10): beyond "
                  "50k vertices the free-boundary Newton steps run without a sparse factor "
                  "(conjugate gradients preconditioned by the coupled 2×2-block multigrid):", "",
                  NO_LIMIT_HEADER]
        lines += no_limit
    body = "\n".join(lines)
    out = root / "bench" / "results" / "defaults.md"
    out.write_text(body + "\n")
    if args.doc:
        args.doc.write_text(replace_block(args.doc.read_text(), "defaults", body))


if __name__ == "__main__":
    main()
