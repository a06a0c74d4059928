#!/usr/bin/env python3
"""Atlases of scan-like meshes, as scanners hand them over before any cleaning (issue: scans).

The meshes are made here from ../shared/meshes/closed models (bench/scan_meshes.py: 1-to-4
subdivision, Gaussian noise along the normals with sigma = 0.15 x the mean edge length, small
holes, floating debris quads, vertex colours), seeded, each with its twin without noise (the same
holes and debris), and cached (never stored in the repository). Every atlas is made by the CLI
as MeshLab stores texture coordinates (float PLY, `--uv-storage float`) and scored from the file
(bench/atlas_score.cpp): the hard gates, charts, L2, L-infinity, the report's seconds and stages,
peak memory, and CPU time over wall time (both cores at work).

    .venv/bin/python bench/scans.py [--build build] [--shared ../shared] [--big]
                                    [--texture-size 8192] [--peers]
                                    [--doc docs/benchmarks.md]

Meshes: armadillo x16 (1.38M faces), tuned on; fertility x64 (0.58M faces, genus 4), kept out of
the tuning and reported apart. --big adds armadillo x64 (5.5M) and cheburashka x1024 (13.7M).
Writes bench/results/scans.md and, with --doc, that file's bench:scans block.

--peers runs, instead, this project, xatlas 0.0.11 and Blender 5.0.1 (.venv-blender) on armadillo
x16 with noise, each with a 20-minute limit, scored from each tool's own OBJ as the atlas bench
scores them; it writes bench/results/scans_peers.md and the bench:scans-peers block."""
import argparse
import json
import os
import pathlib
import subprocess
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(HERE))
from atlas import LABELS, hard_gates_ok, run_method, run_with_rusage, write_off  # noqa: E402
from run import replace_block, results_link  # noqa: E402
from scan_meshes import make_scan, write_ply  # noqa: E402

CACHE = pathlib.Path.home() / ".cache" / "straightest-param" / "bench" / "scans"
# (name, source model, subdivisions, holes, debris, held out of the tuning)
MESHES = [("armadillo x16", "armadillo.obj", 2, 2000, 200, False),
          ("fertility x64", "fertility.off", 3, 500, 100, True)]
BIG = [("armadillo x64", "armadillo.obj", 3, 5000, 500, False),
       ("cheburashka x1024", "cheburashka.off", 5, 5000, 500, False)]
SIGMAS = [0.0, 0.15]
PEER_LIMIT = 1200.0  # seconds per peer on the 1.4M-face scan


def load(path):
    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    m = ms.current_mesh()
    return m.vertex_matrix(), m.face_matrix()


def scan_file(shared, name, source, subdivisions, holes, debris, sigma):
    path = CACHE / f"{name.replace(' ', '_')}_s{sigma:g}.ply"
    if not path.exists():
        V, F = load(shared / "meshes" / "closed" / source)
        SV, SF, colours = make_scan(V, F, subdivisions, sigma, holes, debris, seed=1)
        CACHE.mkdir(parents=True, exist_ok=True)
        write_ply(path, SV, SF, colours)
    return path


def run_ours(args, mesh, folder, picture=None):
    out = folder / "ours.ply"
    report_path = folder / "ours.json"
    command = [str(args.build / "bin" / "straightest_param"), str(mesh), str(out), "--atlas",
               "--texture-size", str(args.texture_size), "--uv-storage", "float", "--quiet",
               "--report", str(report_path), "--progress"]
    started = time.monotonic()
    before = os.times()
    _, err, code, peak_mb = run_with_rusage(command)
    wall = time.monotonic() - started
    after = os.times()
    cpu = (after.children_user - before.children_user) + (after.children_system -
                                                          before.children_system)
    row = {"peak_mb": peak_mb, "wall": wall, "cpu_over_wall": cpu / wall if wall > 0 else 0}
    if code != 0:
        row["failed"] = (err.strip().splitlines() or [f"exit {code}"])[-1][:200]
        return row
    report = json.loads(report_path.read_text())
    row.update({k: report[k] for k in ("charts", "charts_split", "l2_stretch", "linf_stretch",
                                        "seconds", "faces", "components")})
    row["stage_seconds"] = report.get("stage_seconds", {})
    row["stage_cpu_seconds"] = report.get("stage_cpu_seconds", {})
    row["progress_gaps"] = progress_gaps(err)
    (folder / "progress.log").write_text(err)  # to find where the bar waits
    score = subprocess.run([str(args.build / "bin" / "sdp_atlas_score"), str(out),
                            str(args.texture_size), "2"], capture_output=True, text=True)
    if score.returncode != 0:
        row["failed"] = "scorer: " + score.stderr.strip()[:150]
        return row
    row["scored"] = json.loads(score.stdout)
    if picture:
        from scan_picture import picture as draw
        draw(out, picture[0], picture[1])
        row["picture"] = picture[0]
    out.unlink()  # hundreds of MB at the big sizes
    return row


def progress_gaps(stderr):
    """The longest wait, in seconds, for a call of the progress callback, for a move of its
    percentage, and for a move of the stage's own bar (what MeshLab's bar shows for the atlas),
    from the CLI's --progress lines."""
    calls, stage_moves = [], []
    for line in stderr.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[0] == "progress":
            calls.append((float(parts[3]), int(parts[2].rstrip("%"))))
        elif len(parts) == 5 and parts[0] == "stage":
            stage_moves.append((float(parts[4]), parts[1], int(parts[2].rstrip("%"))))
    if len(calls) < 2:
        return None
    moves = [c for i, c in enumerate(calls) if i == 0 or c[1] > calls[i - 1][1]]
    longest = lambda points: max(b[0] - a[0] for a, b in zip(points, points[1:])) if len(
        points) > 1 else 0.0
    return longest(calls), longest(moves), longest(stage_moves)


def gates_ok(scored):
    return all(scored.get(k) == 0 for k in ("flipped_faces", "mirrored_charts",
                                            "overlapping_pixels", "gutter_violations",
                                            "outside_faces", "uncharted_faces"))


def slowest_stage(row):
    """The stage of more than a second with the lowest CPU over wall time, as 'name ratio'."""
    ratios = [(row["stage_cpu_seconds"].get(k, 0) / v, k)
              for k, v in row["stage_seconds"].items() if v > 1]
    if not ratios:
        return "–"
    ratio, stage = min(ratios)
    return f"{stage} {ratio:.2f}"


def fmt_row(name, sigma, row):
    if "failed" in row:
        return (f"| {name} | {sigma:g} | – | refused: {row['failed']} | – | – | – | "
                f"{row['wall']:.1f} | {row['peak_mb']:.0f} | – | – |")
    s = row["scored"]
    stages = ", ".join(f"{k} {v:.1f}" for k, v in row["stage_seconds"].items())
    gaps = row.get("progress_gaps")
    gaps = " / ".join(f"{g:.1f}" for g in gaps) if gaps else "–"
    return (f"| {name} | {sigma:g} | {row['faces']:,} | "
            f"{'yes' if gates_ok(s) else 'NO'} | {row['charts']} | {s['l2']:.4f} | "
            f"{s['linf']:.2f} | {row['seconds']:.1f} ({stages}) | {row['peak_mb']:.0f} | "
            f"{row['cpu_over_wall']:.2f} ({slowest_stage(row)}) | {gaps} |")


def run_peers(args):
    """This project, xatlas and Blender on armadillo x16 with noise, scored alike (OBJ out)."""
    name, source, subdivisions, holes, debris, _ = MESHES[0]
    mesh = scan_file(args.shared, name, source, subdivisions, holes, debris, 0.15)
    off = CACHE / "armadillo_x16_s0.15.off"  # the peers read OFF
    if not off.exists():
        V, F = load(mesh)
        write_off(off, V, F)
    folder = CACHE / "runs" / "peers"
    folder.mkdir(parents=True, exist_ok=True)
    scoring = argparse.Namespace(build=args.build, texture_size=args.texture_size, gutter=2)
    lines = [f"{name} with noise σ = 0.15 (bench/scans.py --peers): each tool in a process of its "
             f"own with a {PEER_LIMIT / 60:.0f}-minute limit, texture {args.texture_size}², gutter "
             "2, scored from the tool's own OBJ as the atlas bench scores them; seconds are each "
             "tool's own work:", "",
             "| tool | every hard gate | charts | seam | L2 | L∞ | flipped | mirrored | "
             "overlapping px | efficiency | s | peak MB |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for method in ("ours", "xatlas", "blender"):
        started = time.monotonic()
        r = run_method(method, scoring, off, folder, timeout=PEER_LIMIT)
        wall = time.monotonic() - started
        if "failed" in r:
            said = (f"stopped at the {PEER_LIMIT / 60:.0f}-minute limit, no atlas"
                    if "time limit" in r["failed"] else f"failed: {r['failed']}")
            line = f"| {LABELS[method]} | {said} | | | | | | | | | {wall:.0f} | |"
        else:
            line = (f"| {LABELS[method]} | {'yes' if hard_gates_ok(r) else 'NO'} | {r['charts']} | "
                    f"{r['seam']:.1f} | {r['l2']:.4f} | {r['linf']:.3g} | {r['flipped_faces']} | "
                    f"{r['mirrored_charts']} | {r['overlapping_pixels']} | {r['efficiency']:.3f} | "
                    f"{r['seconds']:.1f} | {r['peak_mb']:.0f} |")
        print(line, flush=True)
        lines.append(line)
    body = "\n".join(lines)
    (HERE / "results" / "scans_peers.md").write_text(body + "\n")
    if args.doc:
        doc = pathlib.Path(args.doc)
        text = doc.read_text()
        if "<!-- bench:scans-peers -->" not in text:
            sys.exit(f"scans.py: {doc} has no <!-- bench:scans-peers --> block")
        doc.write_text(replace_block(text, "scans-peers", body))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", type=pathlib.Path, default=REPO / "build")
    parser.add_argument("--shared", type=pathlib.Path, default=REPO.parent / "shared")
    parser.add_argument("--big", action="store_true")
    parser.add_argument("--peers", action="store_true",
                        help="instead of the scans table, this project, xatlas and Blender on "
                             "armadillo x16 with noise (bench:scans-peers)")
    parser.add_argument("--texture-size", type=int, default=8192)
    parser.add_argument("--doc", help="the file holding the bench:scans block (docs/benchmarks.md)")
    parser.add_argument("--only", help="comma-separated mesh names")
    args = parser.parse_args()
    if args.peers:
        return run_peers(args)
    meshes = MESHES + (BIG if args.big else [])
    if args.only:
        meshes = [m for m in meshes if m[0] in args.only.split(",")]
    work = CACHE / "runs"
    lines = [f"Scan-like meshes (bench/scans.py; texture {args.texture_size}², gutter 2, float "
             "texture coordinates as MeshLab stores them; seconds are the report's, without file "
             "I/O; CPU/wall over the whole process, and in brackets the stage of more than a second "
             "with the lowest CPU/wall (the report's stage_cpu_seconds over stage_seconds); "
             "progress: the longest wait for a call of the "
             "progress callback / for its percentage to move / for the stage's own bar to move "
             "(what MeshLab's bar shows), in seconds):", "",
             "| mesh | noise σ | faces | every hard gate | charts | L2 | L∞ | seconds (stages) | "
             "peak MB | CPU / wall | progress s |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    held_out = []
    charts = {}
    pictures = []
    # The largest mesh run, with noise, is pictured (checkerboard and UV layout).
    pictured = max(meshes, key=lambda m: m[2])[0]
    for name, source, subdivisions, holes, debris, out_of_tuning in meshes:
        for sigma in SIGMAS:
            mesh = scan_file(args.shared, name, source, subdivisions, holes, debris, sigma)
            folder = work / f"{name.replace(' ', '_')}_s{sigma:g}"
            folder.mkdir(parents=True, exist_ok=True)
            picture = None
            if name == pictured and sigma > 0:
                picture = (HERE / "results" / f"scans_{name.replace(' ', '_')}.png",
                           f"{name}, noise σ = {sigma:g} x the mean edge")
            row = run_ours(args, mesh, folder, picture)
            if "picture" in row:
                pictures.append((name, sigma, row["picture"]))
            charts[(name, sigma)] = row.get("charts")
            line = fmt_row(name, sigma, row)
            print(line, flush=True)
            (held_out if out_of_tuning else lines).append(line)
    if held_out:
        lines += ["", "Kept out of the tuning:", "", lines[2], lines[3]] + held_out
    ratios = [f"{name} {charts[(name, 0.15)] / charts[(name, 0.0)]:.2f}×"
              for name, *_ in meshes
              if charts.get((name, 0.15)) and charts.get((name, 0.0))]
    if ratios:
        lines += ["", "Charts with noise over charts without (same holes and debris): " +
                  ", ".join(ratios) + " (target ≤ 1.5×)."]
    def with_pictures(link):
        """The lines, then each picture linked by `link(file name)`."""
        out = list(lines)
        for name, sigma, png in pictures:
            out += ["", f"The atlas of {name} with noise σ = {sigma:g}: its checkerboard and its "
                    "UV layout, each chart in a colour of its own:", "",
                    f"![{name}]({link(png.name)})"]
        return "\n".join(out)

    results = HERE / "results"
    results.mkdir(exist_ok=True)
    body = with_pictures(lambda name: name)  # bench/results/scans.md sits beside its pictures
    (results / "scans.md").write_text(body + "\n")
    print(body)
    if args.doc:
        doc = pathlib.Path(args.doc)
        text = doc.read_text()
        if "<!-- bench:scans -->" not in text:
            sys.exit(f"scans.py: {doc} has no <!-- bench:scans --> block")
        body = with_pictures(lambda name: results_link(name, args.doc))
        doc.write_text(replace_block(text, "scans", body))


if __name__ == "__main__":
    main()
