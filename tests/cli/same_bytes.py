#!/usr/bin/env python3
"""The default map is the same bytes on every run: straightest_param with its defaults on MESH,
once on a quiet machine, once beside a CPU hog (a busy process per core) and once on one core
(`taskset -c 0`), each writing OBJ (double, with its .mtl and checkerboard) and PLY (float); the
files of the three runs must be identical byte for byte, and so must the reports' refinement
fields.

usage: same_bytes.py --exe STRAIGHTEST_PARAM --workdir DIR [--mesh MESH]

Without --mesh it runs on a generated bumpy height field of 58k vertices: past the size where the
Newton stage starts with the coarse grid's steps (their face sums split into fixed slots), with
enough faces that the face loops run in several slots; that the free-boundary steps ran is
asserted. (Its refinement now converges within the work budget; the budget's own determinism is
checked on the scans by bench/determinism.py.) bench/determinism.py runs it on the shared meshes.
"""
import argparse
import contextlib
import json
import math
import multiprocessing
import os
import pathlib
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "robustness"))
import meshgen  # noqa: E402

# Report fields that must agree (seconds and stage_seconds may not).
SAME_FIELDS = ["l2_stretch", "linf_stretch", "stretch_iterations", "best_iteration",
               "free_boundary_steps", "refinement_stop", "refinement_work", "stage_work"]
# The atlas's report (--atlas) has its own keys.
ATLAS_SAME_FIELDS = ["charts", "seam", "packing_efficiency", "l2_stretch", "linf_stretch",
                     "texels_per_unit", "chart_fallbacks", "charts_split", "refinement_work"]


def busy():
    while True:
        pass


@contextlib.contextmanager
def cpu_hog():
    """A busy process on every core while the block runs."""
    hogs = [multiprocessing.Process(target=busy, daemon=True) for _ in range(os.cpu_count() or 2)]
    for h in hogs:
        h.start()
    try:
        yield
    finally:
        for h in hogs:
            h.terminate()
            h.join()


def bumpy_patch(path):
    """The 58k-vertex bumpy height field whose refinement the work budget ends."""
    return meshgen.write_off(path, meshgen.grid(
        240, height=lambda x, y: 0.15 * math.sin(9 * x) * math.sin(7 * y) + 0.3 * x * x))


def run(exe, mesh, folder, prefix=(), options=(), outputs=("map.obj", "map.ply")):
    folder.mkdir(parents=True)
    reports = []
    for name in outputs:
        report = folder / (name + ".json")
        done = subprocess.run([*prefix, exe, mesh, folder / name, "--report", report, *options],
                              capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit(f"{folder.name}: straightest_param failed: {done.stderr.strip()}")
        reports.append(json.loads(report.read_text()))
    files = {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.suffix != ".json"}
    return files, reports


def three_runs(exe, mesh, workdir, **how):
    """{run name: (files, reports)} for the quiet, loaded and one-core runs; `how`: run()'s
    options and outputs."""
    results = {"quiet": run(exe, mesh, workdir / "quiet", **how)}
    with cpu_hog():
        results["beside a CPU hog"] = run(exe, mesh, workdir / "hog", **how)
    results["one core"] = run(exe, mesh, workdir / "one_core", prefix=["taskset", "-c", "0"],
                              **how)
    return results


def differences(results, fields=SAME_FIELDS):
    """What differs from the quiet run, one line each."""
    quiet_files, quiet_reports = results["quiet"]
    failures = []
    for name, (files, reports) in results.items():
        if files.keys() != quiet_files.keys():
            failures.append(f"{name}: files {sorted(files)} against {sorted(quiet_files)}")
        for file in quiet_files.keys() & files.keys():
            if files[file] != quiet_files[file]:
                failures.append(f"{name}: {file} differs from the quiet run's")
        for report, quiet in zip(reports, quiet_reports):
            for field in fields:
                if report[field] != quiet[field]:
                    failures.append(f"{name}: {field} {report[field]} against {quiet[field]}")
    return failures


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--exe", required=True)
    parser.add_argument("--mesh")
    parser.add_argument("--workdir", required=True, type=pathlib.Path)
    args = parser.parse_args()
    shutil.rmtree(args.workdir, ignore_errors=True)
    if not args.mesh:
        args.workdir.mkdir(parents=True)
        args.mesh = str(bumpy_patch(args.workdir / "bumps.off"))

    results = three_runs(args.exe, args.mesh, args.workdir)
    quiet_files, quiet_reports = results["quiet"]
    generated = args.mesh == str(args.workdir / "bumps.off")
    for report in quiet_reports:
        if generated and report["free_boundary_steps"] == 0:
            sys.exit("no free-boundary step ran on the generated mesh: the grid's steps were "
                     "not tested")
    failures = differences(results)
    for name, (_, reports) in results.items():
        r = reports[0]
        print(f"{name}: {r['seconds']:.2f} s, L2 {r['l2_stretch']}, {r['stretch_iterations']} "
              f"reweighting + {r['free_boundary_steps']} free-boundary steps, refinement work "
              f"{r['refinement_work']:.3f} x the linear map's")
    if failures:
        sys.exit("not the same bytes:\n  " + "\n  ".join(failures))
    print(f"same bytes in all {len(results)} runs: {', '.join(sorted(quiet_files))}")


if __name__ == "__main__":
    main()
