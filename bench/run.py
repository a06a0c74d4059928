#!/usr/bin/env python3
"""Runs every benchmark of docs/benchmarks.md in one go and writes its tables and plot.

Quality: every shared disk mesh x every weights x boundary pair of ours (+ refined), the CGAL 5.5
peers (Tutte, mean value, discrete conformal, discrete authalic; circle border) and MeshLab's own
Harmonic and LSCM (pymeshlab 2025.7), all scored with the project's metric code.
Paper Table 1 on real meshes. Scaling: 1-to-4 midpoint subdivisions up to 1.65M vertices, time per
stage and peak memory for ours, CGAL mean value and MeshLab Harmonic; a log-log plot.

Called by bench/run.sh (which builds the programs first)."""
import argparse
import csv
import json
import math
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "scripts"))
from marked_block import replace_between  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[1]
SHARED = pathlib.Path(os.environ.get("SDP_SHARED_DIR", REPO.parent / "shared"))
RESULTS = REPO / "bench" / "results"
# The file the benches write their tables into, between <!-- bench:NAME --> markers.
DOC = REPO / "docs" / "benchmarks.md"
DISK = ["nefertiti", "snail", "camel_b", "lilium", "bump-domain", "circle", "camelhead", "face"]
QUICK_DISK = ["nefertiti", "snail", "lilium"]
WEIGHTS = ["straightest", "ltd", "floater", "mean_value", "uniform"]
BOUNDARIES = ["measured", "circle", "square"]
CGAL_METHODS = ["tutte", "mean_value", "conformal", "authalic"]
REFINE_ITERATIONS = 10


def run_json(command):
    done = subprocess.run([str(c) for c in command], capture_output=True, text=True)
    if done.returncode != 0:
        return {"error": (done.stderr.strip() or done.stdout.strip()).splitlines()[-1:]}
    return json.loads(done.stdout)


class Bench:
    def __init__(self, build_dir):
        self.bin = pathlib.Path(build_dir) / "bin"
        self.python = sys.executable

    def ours(self, mesh, subdivisions=0, **options):
        command = [self.bin / "sdp_bench", mesh, subdivisions]
        for key, value in options.items():
            command += ["--" + key.replace("_", "-"), value]
        return run_json(command)

    def cgal(self, mesh, method, subdivisions=0):
        return run_json([self.bin / "sdp_cgal_peer", mesh, method, subdivisions])

    def blender(self, mesh, method):
        """Blender's Unwrap (bench/blender_peer.py) in .venv-blender, which bench/run.sh makes."""
        python = REPO / ".venv-blender" / "bin" / "python"
        if not python.exists():
            return {"error": ["bpy not installed (bench/run.sh installs it)"]}
        return run_json([python, REPO / "bench" / "blender_peer.py", mesh, method,
                         self.bin / "sdp_score"])

    def meshlab(self, mesh, method):
        return run_json([self.python, REPO / "bench" / "meshlab_peer.py", mesh, method,
                         self.bin / "sdp_score"])

    def subdivided(self, mesh, subdivisions, folder):
        if subdivisions == 0:
            return mesh
        out = pathlib.Path(folder) / f"{pathlib.Path(mesh).stem}_s{subdivisions}.off"
        if not out.exists():
            subprocess.run([self.bin / "sdp_bench", mesh, str(subdivisions), "--write-off", out],
                           check=True)
        return out


def fmt(x, digits=4):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "inf"
    return f"{x:.{digits}f}"


def row_of(method, result):
    if "error" in result:
        return {"method": method, "l2": None, "linf": None, "flipped": "error",
                "seconds": None, "note": " ".join(result["error"])}
    return {"method": method, "l2": result.get("l2_stretch"), "linf": result.get("linf_stretch"),
            "flipped": result.get("flipped_faces"), "seconds": result.get("seconds"),
            "note": result.get("boundary_used", "")}


def quality(bench, meshes):
    rows = []
    for name in meshes:
        mesh = SHARED / "meshes/disk" / f"{name}.off"
        print(f"quality: {name}", flush=True)
        for w in WEIGHTS:
            for b in BOUNDARIES:
                rows.append({"mesh": name, **row_of(f"ours {w}/{b}", bench.ours(mesh, weights=w, boundary=b))})
        rows.append({"mesh": name, **row_of(f"ours straightest/measured K={REFINE_ITERATIONS}",
                                            bench.ours(mesh, stretch_iterations=REFINE_ITERATIONS))})
        rows.append({"mesh": name, **row_of(f"ours straightest/measured K={REFINE_ITERATIONS} fixed boundary",
                                            bench.ours(mesh, stretch_iterations=REFINE_ITERATIONS,
                                                       free_boundary=0))})
        for m in CGAL_METHODS:
            rows.append({"mesh": name, **row_of(f"CGAL {m}/circle", bench.cgal(mesh, m))})
        for m in ["harmonic", "lscm"]:
            rows.append({"mesh": name, **row_of(f"MeshLab {m}", bench.meshlab(mesh, m))})
        for m, label in (("slim", "Blender minimum stretch"), ("abf", "Blender angle based")):
            rows.append({"mesh": name, **row_of(label, bench.blender(mesh, m))})
    return rows


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)


def quality_markdown(rows, meshes):
    """One compact table: L2 per mesh for the headline methods, plus flips anywhere."""
    headline = ["ours straightest/measured", f"ours straightest/measured K={REFINE_ITERATIONS} fixed boundary",
                f"ours straightest/measured K={REFINE_ITERATIONS}",
                "ours straightest/circle", "ours ltd/circle", "ours floater/circle",
                "ours mean_value/circle", "CGAL mean_value/circle", "CGAL tutte/circle",
                "CGAL conformal/circle", "CGAL authalic/circle", "MeshLab harmonic", "MeshLab lscm",
                "Blender minimum stretch", "Blender angle based"]
    by = {(r["mesh"], r["method"]): r for r in rows}
    lines = ["| method | " + " | ".join(meshes) + " | folded maps |",
             "|---|" + "---|" * (len(meshes) + 1)]
    for method in headline:
        cells, folded = [], 0
        for name in meshes:
            r = by.get((name, method))
            if r is None:
                cells.append("–")
                continue
            bad = r["flipped"] not in (0, None) and r["flipped"] != "error"
            folded += 1 if bad or r["flipped"] == "error" else 0
            cell = fmt(r["l2"], 3)
            if bad:
                cell += f" ({r['flipped']} flipped)"
            if r["flipped"] == "error":
                cell = "failed"
            cells.append(cell)
        lines.append(f"| {method} | " + " | ".join(cells) + f" | {folded} |")
    ours_rows = [r for r in rows if r["method"].startswith("ours")]
    flipped = sum(1 for r in ours_rows if r["flipped"] not in (0,))
    lines.append("")
    lines.append(f"L2 stretch (1.000 = isometric), lower is better. All {len(ours_rows)} runs of ours "
                 f"(every weights x boundary pair on every mesh, plus refinement): "
                 f"{flipped} with flipped faces.")
    return "\n".join(lines)


def table1(rows, meshes):
    by = {(r["mesh"], r["method"]): r for r in rows}
    cols = [("Floater fixed", "ours floater/circle"), ("LTD fixed", "ours ltd/circle"),
            ("ours fixed", "ours straightest/circle"), ("ours measured", "ours straightest/measured"),
            (f"ours measured + refined, fixed boundary (K={REFINE_ITERATIONS})",
             f"ours straightest/measured K={REFINE_ITERATIONS} fixed boundary"),
            (f"ours measured + refined, free boundary (K={REFINE_ITERATIONS})",
             f"ours straightest/measured K={REFINE_ITERATIONS}")]
    lines = ["| mesh | " + " | ".join(c for c, _ in cols) + " | ours ≤ LTD ≤ Floater (fixed)? | measured < fixed? |",
             "|---|" + "---|" * (len(cols) + 2)]
    holds_order = holds_measured = 0
    for name in meshes:
        vals = [by.get((name, m), {}).get("l2") for _, m in cols]
        linf = [by.get((name, m), {}).get("linf") for _, m in cols]
        order = vals[2] <= vals[1] <= vals[0]
        measured = vals[3] < vals[2]
        note = by.get((name, "ours straightest/measured"), {}).get("note", "")
        holds_order += order
        holds_measured += measured
        cells = [f"{fmt(v)} / {fmt(l, 2)}" for v, l in zip(vals, linf)]
        lines.append(f"| {name} | " + " | ".join(cells) +
                     f" | {'yes' if order else 'no'} | {'yes' if measured else 'no'}"
                     f"{' (fell back to ' + note + ')' if note and note != 'measured' else ''} |")
    lines.append("")
    lines.append(f"Cells: L2 / L∞. The paper's ordering (ours ≤ LTD ≤ Floater with a fixed circle) "
                 f"holds on {holds_order} of {len(meshes)} meshes; the measured boundary beats the "
                 f"fixed one on {holds_measured} of {len(meshes)}.")
    return "\n".join(lines)


def source_rules(bench, meshes):
    """Issue: which automatic source vertex S gives the lower stretch (measured boundary)."""
    lines = ["| mesh | farthest from boundary: L2 (boundary used, walk fallbacks) | "
             "nearest boundary centroid: L2 (boundary used, walk fallbacks) | better |", "|---|---|---|---|"]
    wins = {"farthest": 0, "centroid": 0, "tie": 0}
    for name in meshes:
        mesh = SHARED / "meshes/disk" / f"{name}.off"
        cells, l2 = [], {}
        for rule in ["farthest", "centroid"]:
            r = bench.ours(mesh, source_rule=rule)
            l2[rule] = r["l2_stretch"]
            cells.append(f"{fmt(r['l2_stretch'])} ({r['boundary_used']}, {r['fallback_counts']['walk_fallbacks']})")
        better = "tie" if abs(l2["farthest"] - l2["centroid"]) < 1e-6 else min(l2, key=l2.get)
        wins[better] += 1
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {better} |")
    lines.append("")
    lines.append(f"farthest better on {wins['farthest']}, centroid better on {wins['centroid']}, "
                 f"tie on {wins['tie']} of {len(meshes)} meshes; the default is the farthest rule.")
    return "\n".join(lines)


def refinement(rows, meshes):
    """K=0 against K=10 with the boundary kept (the paper's setting + YBS) and let go (default)."""
    by = {(r["mesh"], r["method"]): r for r in rows}
    k = REFINE_ITERATIONS
    lines = [f"| mesh | L2, K=0 | L2, K={k} fixed boundary | change | L2, K={k} free boundary (default) | change | "
             f"excess (L2−1) change | L∞, K=0 | L∞, K={k} | s, K=0 | s, K={k} | flipped |",
             "|---|" + "---|" * 11]
    fixed_changes, l2_changes, excess_changes = [], [], []
    for name in meshes:
        a = by[(name, "ours straightest/measured")]
        f = by[(name, f"ours straightest/measured K={k} fixed boundary")]
        b = by[(name, f"ours straightest/measured K={k}")]
        fixed_change = f["l2"] / a["l2"] - 1
        change = b["l2"] / a["l2"] - 1
        excess = (b["l2"] - 1) / (a["l2"] - 1) - 1 if a["l2"] - 1 > 1e-3 else None
        fixed_changes.append(fixed_change)
        l2_changes.append(change)
        if excess is not None:
            excess_changes.append(excess)
        lines.append(f"| {name} | {fmt(a['l2'])} | {fmt(f['l2'])} | {fixed_change:+.1%} | {fmt(b['l2'])} | "
                     f"{change:+.1%} | {'–' if excess is None else f'{excess:+.1%}'} | {fmt(a['linf'], 2)} | "
                     f"{fmt(b['linf'], 2)} | {fmt(a['seconds'], 3)} | {fmt(b['seconds'], 3)} | "
                     f"{b['flipped'] + f['flipped']} |")
    lines.append("")
    lines.append(f"Mean L2 change: fixed boundary {np.mean(fixed_changes):+.1%}, free boundary (default) "
                 f"{np.mean(l2_changes):+.1%} (target −30%); mean change of the excess stretch "
                 f"(L2 − 1, meshes not already isometric) with the free boundary {np.mean(excess_changes):+.1%}.")
    return "\n".join(lines)


def holes(bench):
    lines = ["| mesh | boundary | vertices | holes filled | L2 | L∞ | flipped | s |", "|---|---|---|---|---|---|---|---|"]
    runs = [(b, {"boundary": b}) for b in BOUNDARIES] + [
        (f"measured, K={REFINE_ITERATIONS}", {"stretch_iterations": REFINE_ITERATIONS})]
    for name in ["beetle", "halftunnel_quads"]:
        mesh = SHARED / "meshes/holes" / f"{name}.off"
        for label, options in runs:
            r = bench.ours(mesh, **options)
            if "error" in r:
                lines.append(f"| {name} | {label} | – | – | failed: {' '.join(r['error'])} | | | |")
                continue
            lines.append(f"| {name} | {label} ({r['boundary_used']}) | {r['vertices']:,} | {r['holes_filled']} | "
                         f"{fmt(r['l2_stretch'])} | {fmt(r['linf_stretch'], 2)} | {r['flipped_faces']} | "
                         f"{fmt(r['seconds'], 3)} |")
    return "\n".join(lines)


def renders(bench, folder):
    """Checkerboard, stretch map and layout of a few meshes, drawn from the CLI's own output."""
    refine = ["--stretch-iterations", str(REFINE_ITERATIONS)]
    cases = [("nefertiti", "nefertiti", [], ""), ("lilium", "lilium", [], ""), ("face", "face", [], ""),
             ("face", "face_refined", refine, f", {REFINE_ITERATIONS} stretch iterations"),
             ("camel_b", "camel_b_refined_fixed", refine + ["--fixed-boundary"],
              f", {REFINE_ITERATIONS} stretch iterations, boundary kept"),
             ("camel_b", "camel_b_refined_free", refine,
              f", {REFINE_ITERATIONS} stretch iterations, boundary let go")]
    lines = []
    for name, tag, extra, what in cases:
        mesh = SHARED / "meshes/disk" / f"{name}.off"
        obj = pathlib.Path(folder) / f"{tag}.obj"
        report = json.loads(subprocess.run([bench.bin / "straightest_param", mesh, obj, *extra],
                                           check=True, capture_output=True, text=True).stdout)
        png = RESULTS / f"render_{tag}.png"
        title = (f"{name}: straightest + {report['boundary_used']}{what} — L2 {report['l2_stretch']:.3f}, "
                 f"L∞ {report['linf_stretch']:.2f}, {report['flipped_faces']} flipped")
        subprocess.run([sys.executable, REPO / "bench/render.py", obj, png, "--title", title], check=True)
        lines.append(f"![{tag}]({results_link(png.name)})")
    return "\n\n".join(lines)


def scaling(bench, quick, folder):
    """face.off subdivided 0..3 times (26k .. 1.65M vertices), plus lilium x4 (~867k)."""
    cases = [("face", k) for k in ([0, 1] if quick else [0, 1, 2, 3])]
    if not quick:
        cases.append(("lilium", 4))
    rows = []
    for name, k in cases:
        base = SHARED / "meshes/disk" / f"{name}.off"
        print(f"scaling: {name} x{k}", flush=True)
        ours = bench.ours(base, k)
        row = {"mesh": f"{name} s{k}", "vertices": ours.get("vertices"),
               "ours_seconds": ours.get("seconds"), "ours_extra_mb": ours.get("extra_mb"),
               "ours_l2": ours.get("l2_stretch"), "ours_flipped": ours.get("flipped_faces")}
        for stage, seconds in ours.get("stage_seconds", {}).items():
            row[f"ours_{stage}"] = seconds
        if True:  # CGAL at every size: the 50x target is judged at >= 200k vertices
            cgal = bench.cgal(base, "mean_value", k)
            row.update({"cgal_mvc_seconds": cgal.get("seconds"), "cgal_mvc_rss_mb": cgal.get("peak_rss_mb"),
                        "cgal_mvc_flipped": cgal.get("flipped_faces")})
        mesh = bench.subdivided(base, k, folder)
        harmonic = bench.meshlab(mesh, "harmonic")
        row.update({"harmonic_seconds": harmonic.get("seconds"), "harmonic_extra_mb": harmonic.get("extra_mb"),
                    "harmonic_flipped": harmonic.get("flipped_faces")})
        rows.append(row)
    return rows


def scaling_markdown(rows):
    lines = ["| mesh | vertices | ours s | topology | weights | boundary | solve | metrics | ours extra MB (B/vertex) "
             "| CGAL MVC s | × CGAL | MeshLab Harmonic s | × Harmonic |",
             "|---|" + "---|" * 12]
    for r in rows:
        v = r["vertices"] or 0
        ours = r["ours_seconds"] or float("nan")
        cgal = r.get("cgal_mvc_seconds")
        harm = r.get("harmonic_seconds")
        per_vertex = (r["ours_extra_mb"] or 0) * 1048576 / max(v, 1)
        lines.append(
            f"| {r['mesh']} | {v:,} | {fmt(ours, 3)} | " +
            " | ".join(fmt(r.get(f"ours_{s}"), 3) for s in ["topology", "weights", "boundary", "solve", "metrics"]) +
            f" | {fmt(r['ours_extra_mb'], 0)} ({per_vertex:.0f}) | {fmt(cgal, 2) if cgal else '–'} | "
            f"{fmt(cgal / ours, 1) + '×' if cgal else '–'} | {fmt(harm, 2) if harm else '–'} | "
            f"{fmt(harm / ours, 1) + '×' if harm else '–'} |")
    lines.append("")
    lines.append("Weights and boundary run at the same time (the boundary on one core while the weights start "
                 "on the other), so those two columns overlap; `ours s` is the wall time of the whole run.")
    big = [r for r in rows if (r["vertices"] or 0) >= 200000]
    cgal_ratios = [(r["mesh"], r["vertices"], r["cgal_mvc_seconds"] / r["ours_seconds"])
                   for r in big if r.get("cgal_mvc_seconds")]
    harmonic_ratios = [(r["mesh"], r["vertices"], r["harmonic_seconds"] / r["ours_seconds"])
                       for r in rows if r.get("harmonic_seconds") and 600000 <= (r["vertices"] or 0) <= 1000000]
    if cgal_ratios:
        lines.append("")
        lines.append("Against CGAL mean value at ≥ 200k vertices (target ≥ 50×): " + "; ".join(
            f"{m} ({v:,} vertices) {x:.1f}× {'(met)' if x >= 50 else '(not met)'}" for m, v, x in cgal_ratios) + ".")
    if harmonic_ratios:
        lines.append("Against MeshLab Harmonic at ~800k vertices (target ≥ 8×): " + "; ".join(
            f"{m} ({v:,} vertices) {x:.1f}× {'(met)' if x >= 8 else '(not met)'}" for m, v, x in harmonic_ratios) + ".")
    face = [r for r in rows if r["mesh"].startswith("face") and r["vertices"] and r["vertices"] >= 50000]
    if len(face) >= 2:
        a, b = face[0], face[-1]
        exponent = math.log(b["ours_seconds"] / a["ours_seconds"]) / math.log(b["vertices"] / a["vertices"])
        lines.append("")
        lines.append(f"Growth exponent of ours from {a['vertices']:,} to {b['vertices']:,} vertices: "
                     f"{exponent:.2f} (time ∝ V^exponent; 1.0 = linear).")
    return "\n".join(lines)


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    face = [r for r in rows if r["mesh"].startswith("face")]
    fig, ax = plt.subplots(figsize=(6.4, 4.2), dpi=110)
    for key, label in [("ours_seconds", "ours (straightest + measured)"),
                       ("cgal_mvc_seconds", "CGAL mean value"), ("harmonic_seconds", "MeshLab Harmonic")]:
        pts = [(r["vertices"], r[key]) for r in face if r.get(key)]
        if pts:
            ax.loglog(*zip(*pts), marker="o", label=label)
    ax.set_xlabel("vertices (face.off, 1-to-4 subdivisions)")
    ax.set_ylabel("seconds")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path)


def results_link(name, doc=DOC):
    """bench/results/NAME as a Markdown link target from the file DOC (docs/benchmarks.md:
    ../bench/results/NAME), so that the pictures and files a block links to resolve where it is."""
    return os.path.relpath(RESULTS / name, pathlib.Path(doc).resolve().parent)


def replace_block(text, name, body):
    """`text` with its <!-- bench:NAME --> block's body replaced by `body` (a file without the
    block is left as it is)."""
    replaced = replace_between(text, f"<!-- bench:{name} -->\n", f"<!-- /bench:{name} -->",
                               body + "\n")
    return text if replaced is None else replaced


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build-dir", default=str(REPO / "build"))
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    bench = Bench(args.build_dir)
    RESULTS.mkdir(parents=True, exist_ok=True)
    meshes = QUICK_DISK if args.quick else DISK

    rows = quality(bench, meshes)
    write_csv(RESULTS / "quality.csv", rows)
    blocks = {"quality": quality_markdown(rows, meshes), "table1": table1(rows, meshes),
              "refinement": refinement(rows, meshes), "source": source_rules(bench, meshes),
              "holes": holes(bench)}
    with tempfile.TemporaryDirectory() as folder:
        blocks["renders"] = renders(bench, folder)
        scale_rows = scaling(bench, args.quick, folder)
    write_csv(RESULTS / "scaling.csv", scale_rows)
    blocks["scaling"] = scaling_markdown(scale_rows)
    plot(scale_rows, RESULTS / "scaling.png")
    # The blocks link to bench/results/ from DOC's folder; the results files sit in it.
    from_doc = os.path.relpath(RESULTS, DOC.parent) + "/"
    for name, body in blocks.items():
        (RESULTS / f"{name}.md").write_text(body.replace(f"]({from_doc}", "](") + "\n")
        print(f"\n## {name}\n{body}")
    if not args.quick:
        text = DOC.read_text()
        for name, body in blocks.items():
            text = replace_block(text, name, body)
        DOC.write_text(text)
        # The README's short table against the peers reads quality.csv (and atlas.csv).
        import summary
        summary.update()


if __name__ == "__main__":
    main()
