#!/usr/bin/env python3
"""Atlases of whole models, every method scored by the project's own measures from the file it
wrote (bench/atlas_score.cpp over core/atlas/measure.h): charts, seam, L2, L-infinity, flipped
faces, mirrored charts, overlapping pixels and gutter violations at the texture size, efficiency,
seconds (each tool's own work) and peak memory (each tool runs in a process of its own).

    python3 bench/atlas.py [--build build] [--shared ../shared] [--big | --cad] [--doc docs/benchmarks.md]
                           [--texture-size 4096] [--gutter 2] [--xatlas-big-limit 2400]
                           [--brute-limit 30] [--methods ours,xatlas,...] [--only MODEL,...]

Methods: ours (straightest_param --atlas), xatlas 0.0.11 (defaults, and bruteForce packing),
Geogram 1.9.3's atlas maker (pip geotex 0.1.3 with its defaults: ABF++ charts, xatlas packing;
bench/atlas_peers.py), Blender 5.0.1 (Smart UV Project, Minimum Stretch, Pack Islands:
bench/blender_atlas_peer.py, in .venv-blender), MeshLab's Voronoi Atlas and Trivial Per-Triangle
(pymeshlab). Meshes: the shared closed/ models, pymeshlab's sample models, and with --big
closed/armadillo.obj subdivided 1-to-4 twice (1.38M faces; xatlas there once, under a time
limit). Every model is first written as one triangle OFF (read by pymeshlab), so that every method
gets the same triangles.

With --cad the models are instead the 32 generated CAD/mechanical ones of bench/cad_models.py
(a quarter held out of tuning, reported apart), the methods by default ours, xatlas and geotex.

Writes bench/results/atlas.md, atlas.csv, atlas_*.png and, with --doc, that file's bench:atlas
block; with --cad, atlas_cad.md, atlas_cad.csv, atlas_cad_<model>.png and the
bench:atlas-cad block instead, so that neither run overwrites the other's."""
import argparse
import csv
import json
import os
import pathlib
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(HERE))
from run import replace_block, results_link  # noqa: E402

METHODS = ["ours", "xatlas", "xatlas-brute", "geotex", "blender", "voronoi", "trivial"]
LABELS = {
    "ours": "this project",
    "xatlas": "xatlas 0.0.11",
    "xatlas-brute": "xatlas, bruteForce",
    "geotex": "Geogram 1.9.3 atlas (geotex 0.1.3)",
    "blender": "Blender 5.0.1",
    "voronoi": "MeshLab Voronoi Atlas",
    "trivial": "MeshLab Trivial Per-Triangle",
}


def write_off(path, V, F):
    with open(path, "w") as out:
        out.write(f"OFF\n{len(V)} {len(F)} 0\n")
        out.write("".join(f"{x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in V))
        out.write("".join(f"3 {a} {b} {c}\n" for a, b, c in F))


def subdivide(V, F):
    """1-to-4 midpoint subdivision (each edge's midpoint made once)."""
    edges = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    unique, inverse = np.unique(edges, axis=0, return_inverse=True)
    mid = len(V) + inverse.reshape(3, -1).T  # per face: midpoints of edges 01, 12, 20
    V2 = np.concatenate([V, 0.5 * (V[unique[:, 0]] + V[unique[:, 1]])])
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    m01, m12, m20 = mid[:, 0], mid[:, 1], mid[:, 2]
    F2 = np.concatenate([np.stack(t, 1) for t in
                         ([a, m01, m20], [m01, b, m12], [m20, m12, c], [m01, m12, m20])])
    return V2, F2


BIG_METHODS = "ours,xatlas,blender"
# The CAD set's peers: the atlas makers a CAD pipeline would call (Blender and MeshLab's filters
# are on the default set); --methods overrides.
CAD_METHODS = "ours,xatlas,geotex"
CAD_EFFICIENCY_TARGET = 0.72
XATLAS_BIG_LIMIT = 2400.0


def prepare_models(shared, cache, big):
    """(name, triangle OFF path) for every model, written once into `cache`."""
    import pymeshlab
    sources = sorted(p for p in (shared / "meshes" / "closed").glob("*.*")
                     if p.suffix.lower() in (".off", ".obj", ".ply"))
    samples = pathlib.Path(pymeshlab.__file__).parent / "tests" / "sample_meshes"
    sources += [samples / n for n in ("bunny.obj", "cow.obj", "airplane.obj", "bone.ply")]
    models = []
    for source in sources:
        if not source.exists():
            print(f"atlas bench: {source} missing, left out", file=sys.stderr)
            continue
        name = source.stem if source.parent.name == "closed" else f"{source.stem} (pymeshlab)"
        target = cache / (name.replace(" ", "_").replace("(", "").replace(")", "") + ".off")
        if not target.exists():
            ms = pymeshlab.MeshSet()
            ms.load_new_mesh(str(source))
            m = ms.current_mesh()
            write_off(target, m.vertex_matrix(), m.face_matrix())
        models.append((name, target))
    if big:
        target = cache / "armadillo_x16.off"
        if not target.exists():
            ms = pymeshlab.MeshSet()
            ms.load_new_mesh(str(shared / "meshes" / "closed" / "armadillo.obj"))
            V, F = ms.current_mesh().vertex_matrix(), ms.current_mesh().face_matrix()
            for _ in range(2):
                V, F = subdivide(V, F)
            write_off(target, V, F)
        models.append(("armadillo x16 (1.38M faces)", target))
    return models


def run_with_rusage(command, timeout=None):
    """Runs `command` in its own process; returns (stdout, stderr, returncode, peak MB)."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        process = subprocess.Popen(command, stdout=out, stderr=err, text=True)
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            pid, status, usage = os.wait4(process.pid, os.WNOHANG)
            if pid:
                break
            if deadline is not None and time.monotonic() > deadline:
                process.kill()
                _, status, usage = os.wait4(process.pid, 0)
                process.returncode = -9
                out.seek(0)
                return out.read(), f"stopped at the time limit of {timeout} s", -9, None
            time.sleep(0.05)
        process.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        return out.read(), err.read(), process.returncode, usage.ru_maxrss / 1024.0


def method_command(method, args, mesh, out_obj):
    size, gutter = str(args.texture_size), str(args.gutter)
    venv = REPO / ".venv" / "bin" / "python"
    if method == "ours":
        return [str(args.build / "bin" / "straightest_param"), str(mesh), str(out_obj), "--atlas",
                "--texture-size", size, "--gutter", gutter, "--quiet", "--report",
                str(out_obj.with_suffix(".json"))]
    if method == "blender":
        return [str(REPO / ".venv-blender" / "bin" / "python"),
                str(HERE / "blender_atlas_peer.py"), str(mesh), str(out_obj), size, gutter]
    return [str(venv), str(HERE / "atlas_peers.py"), method, str(mesh), str(out_obj), size, gutter]


def run_method(method, args, mesh, folder, timeout=None):
    out_obj = folder / f"{method}.obj"
    out, err, code, peak_mb = run_with_rusage(method_command(method, args, mesh, out_obj), timeout)
    row = {"method": method, "peak_mb": peak_mb}
    if code != 0 or not out_obj.exists():
        row["failed"] = (err.strip().splitlines() or [f"exit {code}"])[-1][:160]
        return row
    if method == "ours":
        report = json.loads(out_obj.with_suffix(".json").read_text())
        row["seconds"] = report["seconds"]
        row["stage_seconds"] = report.get("stage_seconds", {})
    else:
        said = json.loads(out.strip().splitlines()[-1])
        if "refused" in said:
            row["failed"] = said["refused"][:160]
            return row
        row.update(said)
    weld = ["--weld"] if method == "voronoi" else []
    score = subprocess.run([str(args.build / "bin" / "sdp_atlas_score"), str(out_obj),
                            str(args.texture_size), str(args.gutter)] + weld,
                           capture_output=True, text=True)
    if score.returncode != 0:
        row["failed"] = "scorer: " + score.stderr.strip()[:150]
        return row
    scored = json.loads(score.stdout)
    # null: not finite (a UV triangle of no area stretches without bound).
    for key in ("seam", "efficiency", "l2", "linf"):
        if scored[key] is None:
            scored[key] = float("inf")
    row.update(scored)
    row["obj"] = out_obj
    return row


def hard_gates_ok(r):
    return (r.get("flipped_faces") == 0 and r.get("mirrored_charts") == 0 and
            r.get("overlapping_pixels") == 0 and r.get("gutter_violations") == 0 and
            r.get("outside_faces") == 0 and r.get("uncharted_faces") == 0)


def fmt(value, spec):
    return "–" if value is None else format(value, spec)


def table(rows_by_model, methods):
    head = ("| model | method | charts | seam | L2 | L∞ | flipped | mirrored | overlapping px | "
            "gutter px | efficiency | s | peak MB |\n"
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n")
    lines = []
    for model, rows in rows_by_model:
        input_faces = next((r["faces"] for r in rows if r["method"] == "ours" and "faces" in r),
                           None)
        for r in rows:
            if r["method"] not in methods:
                continue
            label = LABELS[r["method"]]
            if input_faces is not None and r.get("faces", input_faces) != input_faces:
                label += f" ({r['faces']} faces written for {input_faces})"
            if "failed" in r:
                lines.append(f"| {model} | {label} | failed: {r['failed']} "
                             "| | | | | | | | | | |")
                continue
            lines.append(
                f"| {model} | {label} | {r['charts']} | {fmt(r['seam'], '.1f')} | "
                f"{fmt(r['l2'], '.4f')} | {fmt(r['linf'], '.3g')} | {r['flipped_faces']} | "
                f"{r['mirrored_charts']} | {r['overlapping_pixels']} | {r['gutter_violations']} | "
                f"{fmt(r['efficiency'], '.3f')} | {fmt(r.get('seconds'), '.2f')} | "
                f"{fmt(r.get('peak_mb'), '.0f')} |")
    return head + "\n".join(lines) + "\n"


def summary_figures(rows_by_model, efficiency_target=0.70, cad=False):
    """The models where ours and xatlas (defaults) both ran, and the set-level figures of the
    issue's targets over them: (measure, ours, xatlas, ratio, target) rows, as printed. For the
    CAD set charts and seam are held to xatlas's own (it keeps flat faces whole too)."""
    common = []
    for model, rows in rows_by_model:
        by = {r["method"]: r for r in rows}
        if "failed" in by.get("ours", {"failed": 1}) or "failed" in by.get("xatlas", {"failed": 1}):
            continue
        common.append((model, by["ours"], by["xatlas"]))
    if not common:
        return common, []
    total = lambda key, who: sum(t[who][key] for t in common)  # noqa: E731
    ours_rows = [t[1] for t in common]
    xa_rows = [t[2] for t in common]
    return common, [
        ("models passing every hard gate", f"{sum(hard_gates_ok(r) for r in ours_rows)}",
         f"{sum(hard_gates_ok(r) for r in xa_rows)}", "", "all"),
        ("models with seam ≤ max(1.5× xatlas's, xatlas's + 2)",
         f"{sum(o['seam'] <= max(1.5 * x['seam'], x['seam'] + 2) for _, o, x in common)}", "–", "",
         "all"),
        ("largest L2", f"{max(r['l2'] for r in ours_rows):.4f}",
         f"{max(r['l2'] for r in xa_rows):.4f}", "", "≤ 1.05"),
        ("total charts", f"{total('charts', 1)}", f"{total('charts', 2)}",
         f"{total('charts', 1) / total('charts', 2):.2f}", "≤ 1.0" if cad else "≤ 0.5"),
        ("total seam", f"{total('seam', 1):.1f}", f"{total('seam', 2):.1f}",
         f"{total('seam', 1) / total('seam', 2):.2f}", "≤ 1.0" if cad else "≤ 0.75"),
        ("median L∞", f"{statistics.median(r['linf'] for r in ours_rows):.3g}",
         f"{statistics.median(r['linf'] for r in xa_rows):.3g}", "", "ours below"),
        ("median efficiency", f"{statistics.median(r['efficiency'] for r in ours_rows):.3f}",
         f"{statistics.median(r['efficiency'] for r in xa_rows):.3f}", "",
         f"≥ {efficiency_target:.2f}"),
        ("lowest efficiency", f"{min(r['efficiency'] for r in ours_rows):.3f}",
         f"{min(r['efficiency'] for r in xa_rows):.3f}", "", "≥ 0.60"),
        ("total seconds", f"{total('seconds', 1):.1f}", f"{total('seconds', 2):.1f}",
         f"{total('seconds', 1) / total('seconds', 2):.2f}", "≤ 0.5"),
    ]


def summary(rows_by_model, efficiency_target=0.70, cad=False):
    """Set-level figures of the issue's targets, ours against xatlas (defaults), same run. The
    median efficiency's target is the set's: 0.70 for the default models, 0.72 for the CAD ones
    (their large flat faces pack better)."""
    common, figures = summary_figures(rows_by_model, efficiency_target, cad)
    if not common:
        return "No model with both ours and xatlas.\n"
    lines = [
        f"Over the {len(common)} models where both ran (ours against xatlas with its defaults, "
        "same run):",
        "",
        "| measure | this project | xatlas | ratio | target |",
        "| --- | --- | --- | --- | --- |",
    ] + [f"| {measure} | {ours} | {xa} | " + (f"{ratio} | " if ratio else "| ") + f"{target} |"
         for measure, ours, xa, ratio, target in figures]
    return "\n".join(lines) + "\n"


# xatlas cuts the helical threads of these into one chart per face, which alone outweighs every
# other model in its chart and seam totals; the summaries also give the figures without them.
THREADED = ("bolt_nut_washer", "hex_nut")


def summary_unthreaded(rows_by_model, efficiency_target):
    """One line: summary()'s figures over the same models less the threaded ones."""
    rest = [(model, rows) for model, rows in rows_by_model if model not in THREADED]
    names = " and ".join(THREADED)
    if len(rest) == len(rows_by_model):
        return (f"Neither threaded model ({names}) is among these, so the figures without them "
                "are the table's.\n")
    common, figures = summary_figures(rest, efficiency_target)
    if not common:
        return f"No model other than {names} with both ours and xatlas.\n"
    return (f"Without {names} (xatlas makes one chart per face on their helical threads, which "
            f"dominates its totals), over {len(common)} models, ours against xatlas: " +
            "; ".join(f"{measure} {ours}" + (f" against {xa}" if xa != "–" else "") +
                      (f" (ratio {ratio})" if ratio else "")
                      for measure, ours, xa, ratio, _ in figures) + ".\n")


# The set-level figures per group (issue targets: each group's median efficiency at least 0.72),
# read back from the results files so that either bench run rewrites them: the organic models
# (atlas.csv), the CAD models apart for tuning and held out (atlas_cad.csv), and every model
# of both together, as a user's folder mixes them.
GROUP_EFFICIENCY_TARGET = 0.72
CSV_INTEGERS = ("charts", "flipped_faces", "mirrored_charts", "overlapping_pixels",
                "gutter_violations", "outside_faces", "uncharted_faces")
CSV_NUMBERS = ("seam", "l2", "linf", "efficiency", "seconds")


def rows_from_csv(path):
    """[(model, rows, held_out)] in file order, the rows typed as run_method returns them."""
    models = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            row = {"method": r["method"]}
            if r.get("failed"):
                row["failed"] = r["failed"]
            else:
                for key in CSV_INTEGERS:
                    row[key] = int(float(r[key])) if r.get(key) else None
                for key in CSV_NUMBERS:
                    row[key] = float(r[key]) if r.get(key) else None
            models.setdefault(r["model"], ([], r.get("held_out") == "True"))[0].append(row)
    return [(model, rows, held) for model, (rows, held) in models.items()]


def group_summaries(results):
    """The bench:atlas-groups block, or None while either results file is missing."""
    organic_csv, cad_csv = results / "atlas.csv", results / "atlas_cad.csv"
    if not organic_csv.exists() or not cad_csv.exists():
        return None
    organic = [(m, rows) for m, rows, _ in rows_from_csv(organic_csv)]
    cad = rows_from_csv(cad_csv)
    tuning = [(m, rows) for m, rows, held in cad if not held]
    kept_out = [(m, rows) for m, rows, held in cad if held]
    mixed = organic + [(m, rows) for m, rows, _ in cad]
    target = GROUP_EFFICIENCY_TARGET
    return ("Each group's set-level figures against xatlas (each model's rows from one run; "
            "read back from `bench/results/atlas.csv` and `atlas_cad.csv` by "
            "`python3 bench/atlas.py --groups`, which every run of the atlas bench with `--doc` "
            "also does), so a loss on one group cannot hide behind another.\n\n"
            "#### Organic models\n\n" + summary(organic, target) +
            "\n#### CAD models, tuning\n\n" + summary(tuning, target, cad=True) +
            "\n" + summary_unthreaded(tuning, target) +
            "\n#### CAD models, kept out of the tuning\n\n" +
            summary(kept_out, target, cad=True) + "\n" + summary_unthreaded(kept_out, target) +
            "\n#### Mixed: every organic and CAD model together\n\n" + summary(mixed, target) +
            "\n" + summary_unthreaded(mixed, target))


def write_group_summaries(results, doc):
    body = group_summaries(results)
    text = doc.read_text()
    if body is None or "<!-- bench:atlas-groups -->" not in text:
        print(f"atlas bench: no group figures written to {doc} (results or block missing)",
              file=sys.stderr)
        return
    doc.write_text(replace_block(text, "atlas-groups", body))


BIG_TARGET_SECONDS = 15.0
BIG_TARGET_MB = 6144


def big_summary(rows_by_model):
    """The 1.38M-face model against its targets, and where our time goes (what limits it)."""
    big = [(model, rows) for model, rows in rows_by_model if model.startswith("armadillo x16")]
    if not big:
        return ""
    model, rows = big[0]
    by = {r["method"]: r for r in rows}
    ours = by.get("ours", {"failed": "not run"})
    # The scans issue's targets: 1.2M faces in 15 s; 6 GB is its bound for 13M faces.
    lines = ["", f"{model}, targets ≤ {BIG_TARGET_SECONDS:g} s and ≤ {BIG_TARGET_MB} MB:", ""]
    if "failed" in ours:
        lines.append(f"- this project: failed: {ours['failed']}")
    else:
        stages = list(ours.get("stage_seconds", {}).items())  # the report's {stage: seconds}
        longest = max(stages, key=lambda kv: kv[1]) if stages else None
        met = ours["seconds"] <= BIG_TARGET_SECONDS and ours["peak_mb"] <= BIG_TARGET_MB
        lines.append(
            f"- this project ({'targets met' if met else 'targets NOT met'}): "
            f"{ours['seconds']:.1f} s, {ours['peak_mb']:.0f} MB, "
            f"{ours['charts']} charts, seam {ours['seam']:.1f}, L2 {ours['l2']:.4f}, "
            f"L∞ {ours['linf']:.3g}, efficiency {ours['efficiency']:.3f}, every hard gate "
            f"{'kept' if hard_gates_ok(ours) else 'NOT kept'}; seconds by stage: " +
            ", ".join(f"{k} {v:.1f}" for k, v in stages) +
            (f" (what limits it: {longest[0]})" if longest else ""))
    for method in ("xatlas", "blender"):
        if method in by:
            r = by[method]
            lines.append(f"- {LABELS[method]}: " + (
                f"failed: {r['failed']}" if "failed" in r else
                f"{r['seconds']:.1f} s, {r['peak_mb']:.0f} MB, {r['charts']} charts, "
                f"L2 {fmt(r['l2'], '.4f')}, L∞ {fmt(r['linf'], '.3g')}, {r['flipped_faces']} "
                f"flipped faces, {r['mirrored_charts']} mirrored charts, efficiency "
                f"{r['efficiency']:.3f}"))
    return "\n".join(lines) + "\n"


def method_totals(rows_by_model, methods):
    """One row per method over the models it was run on (the 1.38M-face one aside): how often it
    passed every hard gate, and its totals and medians."""
    lines = ["| method | models written | passing every hard gate | total charts | total seam | "
             "median L2 | median L∞ | median efficiency | total s | largest peak MB |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for method in methods:
        # The 1.38M-face model has its own lines (big_summary), not run by every method.
        tried = [r for model, rows in rows_by_model for r in rows
                 if r["method"] == method and not model.startswith("armadillo x16")]
        done = [r for r in tried if "failed" not in r]
        if not tried:
            continue
        if not done:
            lines.append(f"| {LABELS[method]} | 0 of {len(tried)} | | | | | | | | |")
            continue
        peaks = [r["peak_mb"] for r in done if r.get("peak_mb")]
        lines.append(
            f"| {LABELS[method]} | {len(done)} of {len(tried)} | "
            f"{sum(hard_gates_ok(r) for r in done)} | {sum(r['charts'] for r in done)} | "
            f"{sum(r['seam'] for r in done):.1f} | "
            f"{statistics.median(r['l2'] for r in done):.4f} | "
            f"{statistics.median(r['linf'] for r in done):.3g} | "
            f"{statistics.median(r['efficiency'] for r in done):.3f} | "
            f"{sum(r.get('seconds', 0) for r in done):.1f} | "
            f"{max(peaks) if peaks else 0:.0f} |")
    return "\n".join(lines) + "\n"


def pictures(model, rows, out_png, size=300):
    """Each method's checkerboard on the model and its UV layout, side by side."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    import render

    rows = [r for r in rows if "obj" in r]
    fig, axes = plt.subplots(2, len(rows), figsize=(2.6 * len(rows), 5.4), squeeze=False)
    for column, r in enumerate(rows):
        vertices, texcoords, faces, face_tex = render.read_obj(r["obj"])
        uv = texcoords[face_tex]
        face_id, bary = render.rasterize(vertices, faces, size)
        covered = face_id >= 0
        light = render.shade(vertices, faces, face_id)[..., None]
        pixel_uv = np.einsum("hwk,hwkd->hwd", bary, uv[np.maximum(face_id, 0)])
        image = render.checker_colour(pixel_uv, checkers=32) * light
        image[~covered] = 1.0
        axes[0, column].imshow(image, origin="lower")
        axes[0, column].set_title(LABELS[r["method"]], fontsize=8)
        axes[1, column].add_collection(PolyCollection(uv, facecolors="#4878a8", edgecolors="none"))
        axes[1, column].set_xlim(0, 1)
        axes[1, column].set_ylim(0, 1)
        axes[1, column].set_aspect("equal")
        axes[1, column].set_title(f"{r['charts']} charts, eff. {r['efficiency']:.2f}", fontsize=8)
        for ax in axes[:, column]:
            ax.set_xticks([])
            ax.set_yticks([])
    fig.suptitle(model, fontsize=9)
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    plt.close(fig)


def command_options(args):
    """The options of this run that change its tables, as typed."""
    options = ""
    if args.cad:
        options += " --cad"
        if args.methods and args.methods != CAD_METHODS:
            options += f" --methods {args.methods}"
    if args.big:
        options += " --big"
        if args.big_methods != BIG_METHODS:
            options += f" --big-methods {args.big_methods}"
        if args.xatlas_big_limit != XATLAS_BIG_LIMIT:
            options += f" --xatlas-big-limit {args.xatlas_big_limit:g}"
    return options


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", type=pathlib.Path, default=REPO / "build")
    parser.add_argument("--shared", type=pathlib.Path, default=REPO.parent / "shared")
    parser.add_argument("--texture-size", type=int, default=4096)
    parser.add_argument("--gutter", type=int, default=2)
    parser.add_argument("--big", action="store_true", help="add the 1.38M-face armadillo")
    parser.add_argument("--cad", action="store_true",
                        help="the CAD models of bench/cad_models.py instead (atlas_cad.md)")
    parser.add_argument("--xatlas-big-limit", type=float, default=XATLAS_BIG_LIMIT,
                        help="seconds for xatlas on the 1.38M-face model")
    parser.add_argument("--big-methods", default=BIG_METHODS,
                        help="methods run on the 1.38M-face model")
    parser.add_argument("--brute-limit", type=float, default=30.0,
                        help="seconds for xatlas's bruteForce packing on one model")
    parser.add_argument("--methods", help=f"default all; {CAD_METHODS} with --cad")
    parser.add_argument("--only", help="comma-separated model names (a quick run)")
    parser.add_argument("--doc", type=pathlib.Path,
                        help="the file holding the bench:atlas block (docs/benchmarks.md)")
    parser.add_argument("--groups", action="store_true",
                        help="only rewrite --doc's bench:atlas-groups block from the results "
                        "files (no run)")
    args = parser.parse_args()
    if args.groups:
        if not args.doc:
            parser.error("--groups writes into --doc")
        write_group_summaries(REPO / "bench" / "results", args.doc)
        return
    if args.cad and args.big:
        parser.error("--big adds to the default set, not to --cad")
    args.build = args.build.resolve()
    methods = (args.methods or (CAD_METHODS if args.cad else ",".join(METHODS))).split(",")
    results = REPO / "bench" / "results"
    # Every output of a --cad run is named apart, so that it never overwrites the default run's.
    prefix = "atlas_cad" if args.cad else "atlas"
    held_out = set()
    if args.cad:
        from cad_models import cad_models  # needs manifold3d, which the default set does not
        cache = pathlib.Path.home() / ".cache" / "straightest-param" / "bench" / "cad"
        cad = cad_models(cache)
        models = [(name, path) for name, path, _ in cad]
        held_out = {name for name, _, held in cad if held}
    else:
        cache = pathlib.Path.home() / ".cache" / "straightest-param" / "atlas-bench"
        cache.mkdir(parents=True, exist_ok=True)
        models = prepare_models(args.shared, cache, args.big)
    if args.only:
        models = [m for m in models if m[0] in args.only.split(",")]
    work = pathlib.Path(tempfile.mkdtemp(prefix="atlas-bench-"))
    rows_by_model = []
    csv_rows = []
    for name, mesh in models:
        big = name.startswith("armadillo x16")
        folder = work / mesh.stem
        folder.mkdir()
        rows = []
        for method in methods:
            if big and (method in ("xatlas-brute", "voronoi", "trivial") or
                        method not in args.big_methods.split(",")):
                continue  # one xatlas run at this size; MeshLab's filters are not the peers here
            timeout = (args.xatlas_big_limit if big and method == "xatlas" else
                       args.brute_limit if method == "xatlas-brute" else None)
            r = run_method(method, args, mesh, folder, timeout)
            rows.append(r)
            print(f"{name:28s} {method:13s} " + (f"failed: {r['failed']}" if "failed" in r else
                  f"charts {r['charts']:6d} seam {r['seam']:6.1f} L2 {r['l2']:.4f} "
                  f"Linf {r['linf']:8.3g} flips {r['flipped_faces']} mirr {r['mirrored_charts']} "
                  f"overlap {r['overlapping_pixels']} gutter {r['gutter_violations']} "
                  f"eff {r['efficiency']:.3f} {r.get('seconds', 0):.2f}s "
                  f"{r.get('peak_mb') or 0:.0f}MB"), flush=True)
            csv_rows.append({"model": name, **({"held_out": name in held_out} if args.cad else {}),
                             **{k: v for k, v in r.items() if k != "obj"}})
        rows_by_model.append((name, rows))
    # One picture for the CAD set: a plate of many holes shows how each tool cuts flat faces.
    wanted = ("plate_hole_pattern",) if args.cad else ("bunny", "fertility")
    picture_models = [m for m in wanted if any(n == m for n, _ in rows_by_model)]
    picture_lines = []
    doc_picture_lines = []  # the same, linked from where --doc is (docs/: ../bench/results/)
    for model in picture_models:
        png = results / f"{prefix}_{model}.png"
        pictures(model, dict(rows_by_model)[model], png)
        if args.doc:
            doc_picture_lines.append(f"![{model}: each method's checkerboard and UV layout]"
                                     f"({results_link(png.name, args.doc)})")
        picture_lines.append(f"![{model}: each method's checkerboard and UV layout]"
                             f"({png.name})")  # atlas*.md sits beside its pictures
    keys = sorted({k for r in csv_rows for k in r})
    with open(results / f"{prefix}.csv", "w", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=keys)
        writer.writeheader()
        writer.writerows(csv_rows)
    gates = ("Hard gates: no flipped face, no mirrored chart, no pixel covered twice, the gutter "
             "kept, every face charted inside the unit square. Made by "
             f"`python3 bench/atlas.py{command_options(args)}`.\n\n")
    if args.cad:
        tuning = [(m, rows) for m, rows in rows_by_model if m not in held_out]
        kept_out = [(m, rows) for m, rows in rows_by_model if m in held_out]
        head = (f"{len(rows_by_model)} CAD/mechanical models generated by `bench/cad_models.py` "
                "(constructive solid geometry with manifold3d: gears, brackets, plates with holes, "
                "blades, assemblies of several pieces, thin shells, fasteners, pipes, heat sinks; "
                "large flat faces fan-triangulated into slivers, cylinders of 32-96 segments, "
                f"sharp edges, many holes), {len(kept_out)} of them kept out of the tuning and "
                f"reported apart. Texture {args.texture_size}², gutter {args.gutter} texels; every "
                "figure is computed by `bench/atlas_score.cpp` from the OBJ each tool wrote "
                "itself; seconds are each tool's own work, peak MB its process's (a Python "
                "process for the peers). " + gates)
        # The held-out models are reported apart, never pooled with the tuning ones: pooled,
        # figures tuned on would pass for figures of models never seen.
        short = (head + "#### Tuning models\n\n" +
                 summary(tuning, CAD_EFFICIENCY_TARGET, cad=True) + "\n" +
                 summary_unthreaded(tuning, CAD_EFFICIENCY_TARGET) +
                 "\n#### Kept out of the tuning\n\n" +
                 summary(kept_out, CAD_EFFICIENCY_TARGET, cad=True) + "\n" +
                 summary_unthreaded(kept_out, CAD_EFFICIENCY_TARGET) +
                 f"\n#### Every method, all {len(rows_by_model)} models\n\n" +
                 method_totals(rows_by_model, methods))
        shown = [(f"{m} (held out)" if m in held_out else m, rows) for m, rows in rows_by_model]
    else:
        head = (f"Texture {args.texture_size}², gutter {args.gutter} texels, {len(rows_by_model)} "
                "models; every figure is computed by `bench/atlas_score.cpp` from the OBJ each "
                "method wrote; seconds are each tool's own work, peak MB its process's (a Python "
                "process for the peers). " + gates)
        short = (head + summary(rows_by_model) + big_summary(rows_by_model) + "\n" +
                 method_totals(rows_by_model, methods))
        shown = rows_by_model
    body = short + "\n" + table(shown, methods) + "\n" + "\n\n".join(picture_lines) + "\n"
    (results / f"{prefix}.md").write_text(body)
    print(body)
    if args.doc:
        block = "atlas-cad" if args.cad else "atlas"
        text = args.doc.read_text()
        # replace_block leaves a file without the block's markers as it is, silently.
        if f"<!-- bench:{block} -->" not in text or f"<!-- /bench:{block} -->" not in text:
            print(f"atlas bench: {args.doc} has no bench:{block} block, left as it is",
                  file=sys.stderr)
        else:
            doc_body = (short + f"\nEvery model and method: [bench/results/{prefix}.md]"
                        f"({results_link(prefix + '.md', args.doc)}).\n\n" +
                        "\n\n".join(doc_picture_lines) + "\n")
            args.doc.write_text(replace_block(text, block, doc_body))
        write_group_summaries(results, args.doc)
        if not args.cad:
            # The README's short table against the peers reads atlas.csv (and quality.csv).
            import summary as peers_table  # not `summary`: main() calls this file's summary()
            peers_table.update()
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
