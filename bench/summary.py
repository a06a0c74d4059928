#!/usr/bin/env python3
"""The README's short table of where the project stands against the peers users would pick,
for a patch and for a whole-object atlas, generated from the bench results committed in
bench/results/ (never typed):

  patch  bench/results/quality.csv (bench/run.py): this project (straightest distances, measured
         boundary, refined, K=10, as the quality bench runs it) against MeshLab's Harmonic and
         LSCM and Blender's Minimum Stretch and Angle Based, on the shared disk meshes;
  atlas  bench/results/atlas.csv (bench/atlas.py): this project against xatlas, Blender and
         MeshLab's Voronoi Atlas and Trivial Per-Triangle, on the shared models (the 1.38M-face
         one aside, which not every method runs), with atlas.py's hard gates.

    python3 bench/summary.py --check   fails, naming the block, when README.md differs
    python3 bench/summary.py --write   rewrites the block between <!-- bench:peers --> and its
                                       end marker

bench/run.py and bench/atlas.py --doc call write() after they write their blocks, so a full
bench run keeps the README's numbers generated; a --quick run rewrites the CSV files but not the
docs, and --check then says so. Python 3 standard library only (the test suite runs --check with
the system python3)."""
import argparse
import csv
import math
import os
import pathlib
import statistics
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "scripts"))
from marked_block import update_block  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parent.parent
RESULTS = REPO / "bench" / "results"
BEGIN, END = "<!-- bench:peers -->\n", "<!-- /bench:peers -->"

# (method in quality.csv, label): this project first (the bench's refined run), then the peers.
PATCH_METHODS = [
    ("ours straightest/measured K=10", "this project (straightest, measured, refined K=10)"),
    ("MeshLab harmonic", "MeshLab Harmonic"),
    ("MeshLab lscm", "MeshLab LSCM"),
    ("Blender minimum stretch", "Blender Minimum Stretch"),
    ("Blender angle based", "Blender Angle Based"),
]
# (method in atlas.csv, label), as bench/atlas.py labels them.
ATLAS_METHODS = [
    ("ours", "this project"),
    ("xatlas", "xatlas 0.0.11"),
    ("blender", "Blender 5.0.1 (Smart UV Project)"),
    ("voronoi", "MeshLab Voronoi Atlas"),
    ("trivial", "MeshLab Trivial Per-Triangle"),
]
# bench/atlas.py's hard_gates_ok: every one of these counts is 0.
GATES = ("flipped_faces", "mirrored_charts", "overlapping_pixels", "gutter_violations",
         "outside_faces", "uncharted_faces")


def number(text):
    return float(text) if text not in ("", None) else None


def l2(value):
    return "inf" if math.isinf(value) else f"{value:.4f}"


def patch_rows(path):
    rows = list(csv.DictReader(path.open()))
    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    lines = []
    for method, label in PATCH_METHODS:
        done = [r for r in rows if r["method"] == method]
        if not done:
            sys.exit(f"summary: {path} has no rows of {method!r}")
        values = [number(r["l2"]) for r in done]
        one_to_one = sum(int(r["flipped"]) == 0 for r in done)
        seconds = sum(number(r["seconds"]) for r in done)
        lines.append(f"| patch | {label} | {one_to_one} of {len(done)} | "
                     f"{l2(statistics.median(values))} | {l2(max(values))} | – | "
                     f"{seconds:.2f} |")
    return meshes, lines


def atlas_rows(path):
    rows = [r for r in csv.DictReader(path.open()) if not r["model"].startswith("armadillo x16")]
    models = list(dict.fromkeys(r["model"] for r in rows))
    sizes = {r["texture_size"] for r in rows if r["texture_size"]}
    lines = []
    for method, label in ATLAS_METHODS:
        tried = [r for r in rows if r["method"] == method]
        done = [r for r in tried if not r["failed"]]
        if not done:
            sys.exit(f"summary: {path} has no finished rows of {method!r}")
        passing = sum(all(number(r[g]) == 0 for g in GATES) for r in done)
        values = [number(r["l2"]) for r in done]
        charts = sum(int(r["charts"]) for r in done)
        seconds = sum(number(r["seconds"]) or 0 for r in done)
        lines.append(f"| atlas | {label} | {passing} of {len(tried)} | "
                     f"{l2(statistics.median(values))} | {l2(max(values))} | {charts:,} | "
                     f"{seconds:.1f} |")
    return models, sizes, lines


def markdown(doc):
    meshes, patch = patch_rows(RESULTS / "quality.csv")
    models, sizes, atlas = atlas_rows(RESULTS / "atlas.csv")
    benchmarks = os.path.relpath(REPO / "docs" / "benchmarks.md", doc.resolve().parent)
    size = f"at {'/'.join(sorted(sizes))}² " if sizes else ""
    lines = [
        "| job | tool | one-to-one (patch) / every hard gate kept (atlas) | median L2 | "
        "worst L2 | charts | total s |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ] + patch + atlas + [
        "",
        f"L2: Sander's texture stretch, 1 = isometric, lower is better. Patch: the {len(meshes)} "
        f"shared disk meshes ({', '.join(meshes)}), one-to-one = no flipped face "
        f"(`bench/results/quality.csv`). Atlas: {len(models)} whole models {size}"
        "(the gutter given to every method), hard gates = no flipped face, no mirrored chart, "
        "no pixel covered twice, the gutter kept, every face charted "
        "(`bench/results/atlas.csv`). Generated by "
        f"`python3 bench/summary.py --write`; every method and mesh: [{benchmarks}]"
        f"({benchmarks}).",
    ]
    return "\n".join(lines) + "\n"


def update(path=REPO / "README.md", check=False):
    """Writes the table into PATH's block (check: only compares, and exits naming the block
    when it differs). Returns whether the block was already as generated."""
    return update_block(path, BEGIN, END, markdown(pathlib.Path(path)), check,
                        f"summary: the peers table in {path} differs from "
                        "bench/results/quality.csv and atlas.csv; run python3 bench/summary.py "
                        "--write")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--doc", default=str(REPO / "README.md"),
                        help="the file holding the bench:peers block (default README.md)")
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--check", action="store_true")
    mode.add_argument("--write", action="store_true")
    args = parser.parse_args()
    update(args.doc, check=args.check)


if __name__ == "__main__":
    main()
