#!/usr/bin/env python3
"""The atlas filter on a scan of millions of faces in the MeshLab GUIs users run (issue: scans):
MeshLab 2020.09 (Debian 12) and 2025.07 (Debian sid's, in its root), each under Xvfb, driven
through its menus by tests/gui/meshlab_gui_test.py with the dialog's defaults, while the status
bar's progress bar is read about twice a second (--watch-progress). A one-off check with
screenshots, not part of the suite (minutes per run).

    .venv/bin/python bench/scans_gui.py [--build build] [--shared ../shared]
                                        [--mesh "armadillo x64"]

The mesh is the scans bench's (bench/scans.py, noise and holes and debris), written without its
vertex colours: the GUI test recognizes the untextured mesh by its light grey. Writes
bench/results/scans_gui/ (per version: result.txt, the textured view, a frame while the filter
runs, progress.txt) and bench/results/scans_gui.md."""
import argparse
import pathlib
import shutil
import subprocess
import sys

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(HERE))
import scans  # noqa: E402

ROOTS = pathlib.Path.home() / ".cache" / "straightest-param" / "roots"


def without_colours(source, target):
    """Our scan PLY (float xyz + uchar rgb, uchar-int faces) rewritten with positions only."""
    data = source.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    nv = int(header.split("element vertex ")[1].split()[0])
    nf = int(header.split("element face ")[1].split()[0])
    v = np.frombuffer(data, dtype=[("p", "<f4", (3,)), ("c", "u1", (3,))], count=nv, offset=end)
    f = np.frombuffer(data, dtype=[("n", "u1"), ("i", "<i4", (3,))], count=nf,
                      offset=end + v.nbytes)
    with open(target, "wb") as out:
        out.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {nv}\n"
                   "property float x\nproperty float y\nproperty float z\n"
                   f"element face {nf}\nproperty list uchar int vertex_indices\n"
                   "end_header\n").encode())
        out.write(np.ascontiguousarray(v["p"]).tobytes())
        out.write(f.tobytes())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", type=pathlib.Path, default=REPO / "build")
    parser.add_argument("--shared", type=pathlib.Path, default=REPO.parent / "shared")
    parser.add_argument("--mesh", default="armadillo x64")
    args = parser.parse_args()
    name, source, subdivisions, holes, debris, _ = next(
        m for m in scans.MESHES + scans.BIG if m[0] == args.mesh)
    scan = scans.scan_file(args.shared, name, source, subdivisions, holes, debris, 0.15)
    grey = scans.CACHE / (scan.stem + "_grey.ply")
    if not grey.exists():
        without_colours(scan, grey)
    results = HERE / "results" / "scans_gui"
    results.mkdir(parents=True, exist_ok=True)
    work = scans.CACHE / "gui"
    lines = [f"The atlas filter in the MeshLab GUI on {name} with noise, holes and debris "
             f"({grey.name}, without vertex colours), the dialog's defaults (texture 2048), "
             "driven through the menus under Xvfb (`.venv/bin/python bench/scans_gui.py`):", ""]
    runs = [("2020.09", "meshlab-2020.09",
             ["--prefix", str(args.build / "meshlab-2020.09-gui-prefix")]),
            ("2025.07", "meshlab-2025.07-float",
             ["--root", str(ROOTS / "sid"), "--meshlab-version", "2025.07"])]
    for version, plugin, extra in runs:
        out = work / version
        command = [sys.executable, str(REPO / "tests" / "gui" / "meshlab_gui_test.py"),
                   "--plugin", str(args.build / "plugins" / plugin / "libfilter_straightest_param.so"),
                   "--mesh", str(grey), "--filter", "atlas", "--out", str(out),
                   "--watch-progress", "--apply-timeout", "900", "--total-timeout", "1500",
                   "--min-red", "0.005"] + extra
        run = subprocess.run(command, capture_output=True, text=True)
        checks = [l for l in run.stdout.splitlines() + run.stderr.splitlines()
                  if l.startswith(("PASS", "FAIL"))]
        target = results / version
        target.mkdir(exist_ok=True)
        for picture in ["04_textured.png", "progress_03.png", "progress.txt", "result.txt"]:
            if (out / picture).exists():
                shutil.copyfile(out / picture, target / picture)
        lines += [f"MeshLab {version} ({'passed' if run.returncode == 0 else 'FAILED'}; "
                  f"screenshots in bench/results/scans_gui/{version}/):", ""]
        lines += [f"- `{l}`" for l in checks] + [""]
        print("\n".join(lines[-len(checks) - 3:]), flush=True)
    (HERE / "results" / "scans_gui.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
