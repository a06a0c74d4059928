#!/usr/bin/env python3
"""Same bytes on every run, and what the work model counts (docs/method.md §4).

For every shared disk and holes mesh and face.off subdivided twice (face s2, 414k vertices), the
installed command line (build/bin/straightest_param) runs with its defaults three times: quiet,
beside a CPU hog (one busy process per core) and on one core (`taskset -c 0`), each writing OBJ and
PLY (tests/cli/same_bytes.py does the runs and the comparison). A second table sets each stage's
counted work (report `stage_work`, core/common/work.h) beside its measured seconds from the quiet run.
The atlas runs the same three ways on the scans bench's armadillo x16 without noise (1.36M faces,
bench/scans.py; 8192 texture, float PLY as MeshLab stores it), unless --no-atlas.

    python3 bench/determinism.py [--build build] [--shared ../shared] [--no-atlas]
                                 [--doc docs/benchmarks.md]

Writes bench/results/determinism.md and, with --doc, that file's bench:determinism block.
"""
import argparse
import pathlib
import subprocess
import sys
import tempfile

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests" / "cli"))
from run import replace_block  # noqa: E402
from same_bytes import ATLAS_SAME_FIELDS, differences, three_runs  # noqa: E402

STAGES = ["topology", "weights", "solve", "metrics", "refine", "free_boundary", "newton"]


def atlas_row(args, cli, tmp):
    from scans import MESHES, scan_file  # numpy and pymeshlab: the bench's environment
    name, source, subdivisions, holes, debris, _ = MESHES[0]
    mesh = scan_file(pathlib.Path(args.shared), name, source, subdivisions, holes, debris, 0.0)
    results = three_runs(cli, mesh, tmp / "atlas", outputs=("atlas.ply",),
                         options=("--atlas", "--texture-size", "8192"))
    failures = differences(results, ATLAS_SAME_FIELDS)
    quiet = results["quiet"][1][0]
    seconds = " / ".join(f"{reports[0]['seconds']:.1f}" for _, reports in results.values())
    row = (f"| {name} scan | {quiet['faces']:,} | {quiet['charts']} | {quiet['l2_stretch']:.4f} | "
           f"{seconds} | {'yes' if not failures else 'NO: ' + '; '.join(failures)} |")
    print(row, flush=True)
    return row


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default="build")
    parser.add_argument("--shared", default=str(HERE.parent.parent / "shared"))
    parser.add_argument("--doc", help="the file holding the bench:determinism block "
                                          "(docs/benchmarks.md)")
    parser.add_argument("--no-atlas", action="store_true")
    args = parser.parse_args()
    build = pathlib.Path(args.build)
    cli = build / "bin" / "straightest_param"
    shared = pathlib.Path(args.shared) / "meshes"
    meshes = sorted((shared / "disk").glob("*.off")) + sorted((shared / "holes").glob("*.off"))

    same_rows, work_rows = [], []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        face_s2 = tmp / "face_s2.off"
        subprocess.run([build / "bin" / "sdp_bench", shared / "disk" / "face.off", "2",
                        "--write-off", face_s2], check=True)
        for mesh in meshes + [face_s2]:
            name = mesh.stem.replace("_s2", " s2")
            results = three_runs(cli, mesh, tmp / mesh.stem)
            failures = differences(results)
            quiet = results["quiet"][1][0]
            seconds = " / ".join(f"{reports[0]['seconds']:.2f}" for _, reports in results.values())
            same_rows.append(
                f"| {name} | {quiet['vertices']:,} | {quiet['l2_stretch']:.4f} | "
                f"{quiet['refinement_stop']} | {quiet['refinement_work']:.2f} | {seconds} | "
                f"{'yes' if not failures else 'NO: ' + '; '.join(failures)} |")
            st, sw = quiet["stage_seconds"], quiet["stage_work"]
            cells = []
            for stage in STAGES:
                if stage in sw and sw[stage] > 0 and st.get(stage, 0) > 0:
                    cells.append(f"{sw[stage] / 1e9 / st[stage]:.2f}")
                else:
                    cells.append("–")
            total_work = sum(sw.values()) / 1e9
            total_seconds = sum(st.get(stage, 0) for stage in STAGES)
            work_rows.append(f"| {name} | {total_work:.2f} | {total_seconds:.2f} | " +
                             " | ".join(cells) + " |")
            print(same_rows[-1], flush=True)
        atlas_rows = [] if args.no_atlas else [atlas_row(args, cli, tmp)]

    lines = [
        "Each mesh three times with the defaults (quiet, beside a CPU hog on every core, on one "
        "core with `taskset -c 0`), OBJ and PLY written each time and compared byte for byte "
        "(`.venv/bin/python bench/determinism.py`):",
        "",
        "| mesh | vertices | L2 | refinement stop | refinement work (× linear) | "
        "s: quiet / hog / one core | same bytes (OBJ, .mtl, PNG, PLY, report) |",
        "| --- | --- | --- | --- | --- | --- | --- |",
        *same_rows,
        "",
        *(["The atlas the same way, PLY (float, as MeshLab stores it) and report compared:", "",
           "| mesh | faces | charts | L2 | s: quiet / hog / one core | same bytes (PLY, report) |",
           "| --- | --- | --- | --- | --- | --- |", *atlas_rows, ""] if atlas_rows else []),
        "What the work model counts against what the clock says, quiet run: the work of all "
        "stages (10⁹ units), their seconds, and per stage units per nanosecond (1 would be exact; "
        "the budget needs only the ratios between stages to hold):",
        "",
        "| mesh | work, 10⁹ | seconds | " + " | ".join(STAGES) + " |",
        "| --- | --- | --- | " + " | ".join("---" for _ in STAGES) + " |",
        *work_rows,
    ]
    text = "\n".join(lines) + "\n"
    out = HERE / "results" / "determinism.md"
    out.write_text("# Same bytes on every run\n\n" + text)
    print(f"wrote {out}")
    if args.doc:
        doc = pathlib.Path(args.doc)
        doc.write_text(replace_block(doc.read_text(), "determinism", text))


if __name__ == "__main__":
    main()
