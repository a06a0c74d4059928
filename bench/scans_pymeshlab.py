#!/usr/bin/env python3
"""A scan-like mesh through pymeshlab in one process, as a pymeshlab user runs it (issue: scans):
load the PLY, our atlas at 8192², MeshLab's *Transfer: Vertex Attributes to Texture (1 or 2
meshes)* to bake the vertex colours, save the textured mesh, then MeshLab's *Transfer: Texture to
Vertex Color* to read the colours back and compare them with the originals. Each step's wall
seconds and the process's peak memory are printed; each mesh runs in a process of its own.

    .venv/bin/python bench/scans_pymeshlab.py [--build build] [--shared ../shared]
                                              [--only "armadillo x16"] [--big] [--sigma 0.15]
                                              [--texture-size 8192]

The meshes are the scans bench's (bench/scans.py), made and cached there. Writes
bench/results/scans_pymeshlab.md."""
import argparse
import json
import pathlib
import resource
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parent
sys.path.insert(0, str(HERE))
ATLAS = "compute_texcoord_parametrization_straightest_distances_atlas"


def one_mesh(args):
    """Runs in the child: the whole pipeline on args.mesh, a JSON line on stdout."""
    import numpy as np
    import pymeshlab as ml
    plugin = args.build / "plugins" / "meshlab-2025.07" / "libfilter_straightest_param.so"
    if ATLAS not in ml.filter_list():
        ml.load_plugin(str(plugin))
    if not hasattr(ml.MeshSet, ATLAS):
        setattr(ml.MeshSet, ATLAS, ml.bind_function(ATLAS))
    work = pathlib.Path(tempfile.mkdtemp(prefix="scans-pymeshlab-"))
    seconds, peak_after = {}, {}

    def peak_mb():
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

    started = time.monotonic()
    ms = ml.MeshSet()
    ms.load_new_mesh(str(args.mesh))
    seconds["load"] = time.monotonic() - started
    peak_after["load"] = peak_mb()
    mesh = ms.current_mesh()
    faces = mesh.face_matrix()
    face_count = len(faces)
    colours = mesh.vertex_color_matrix()[:, :3].copy()
    used = np.zeros(len(colours), dtype=bool)
    used[faces.ravel()] = True
    del faces
    step = time.monotonic()
    report = getattr(ms, ATLAS)(texturesize=args.texture_size, texturename="atlas.png")
    seconds["atlas"] = time.monotonic() - step
    peak_after["atlas"] = peak_mb()
    step = time.monotonic()
    ms.transfer_attributes_to_texture_per_vertex(sourcemesh=0, targetmesh=0,
                                                 textname="baked.png", textw=args.texture_size,
                                                 texth=args.texture_size)
    seconds["bake"] = time.monotonic() - step
    peak_after["bake"] = peak_mb()
    step = time.monotonic()
    ms.save_current_mesh(str(work / "baked.ply"))
    seconds["save"] = time.monotonic() - step
    peak_after["save"] = peak_mb()
    step = time.monotonic()
    ms.transfer_texture_to_color_per_vertex()
    seconds["read_back"] = time.monotonic() - step
    peak_after["read_back"] = peak_mb()
    difference = np.abs(ms.current_mesh().vertex_color_matrix()[:, :3] - colours)[used] * 255
    seconds["total"] = time.monotonic() - started
    print(json.dumps({
        "faces": face_count, "charts": int(report["charts"]),
        "l2": report["l2_stretch"], "atlas_report_seconds": report["seconds"],
        "seconds": seconds, "colour_difference_mean": float(difference.mean()),
        "colour_difference_max": float(difference.max()),
        "peak_mb": peak_mb(), "peak_mb_after": peak_after}))


def peak_step(peak_after):
    """The first step after which the process's peak memory was reached."""
    highest = max(peak_after.values())
    return next(step for step, mb in peak_after.items() if mb == highest).replace("_", " ")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", type=pathlib.Path, default=REPO / "build")
    parser.add_argument("--shared", type=pathlib.Path, default=REPO.parent / "shared")
    parser.add_argument("--only", default="armadillo x16")
    parser.add_argument("--big", action="store_true", help="the 5.5M and 13.7M meshes too")
    parser.add_argument("--sigma", type=float, default=0.15)
    parser.add_argument("--texture-size", type=int, default=8192)
    parser.add_argument("--mesh", type=pathlib.Path, help=argparse.SUPPRESS)  # the child's
    args = parser.parse_args()
    if args.mesh:
        one_mesh(args)
        return
    from scans import BIG, MESHES, scan_file
    names = args.only.split(",")
    wanted = [m for m in MESHES + BIG if m[0] in names or (args.big and m in BIG)]
    lines = ["| mesh | σ | faces | charts | atlas L2 | seconds: load, atlas, bake, save, "
             "read back (total) | peak MB (whole process), the step that reached it | colours read "
             "back, mean / largest difference (of 255) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for name, source, subdivisions, holes, debris, _ in wanted:
        mesh = scan_file(args.shared, name, source, subdivisions, holes, debris, args.sigma)
        run = subprocess.run([sys.executable, __file__, "--build", str(args.build), "--mesh",
                              str(mesh), "--texture-size", str(args.texture_size)],
                             capture_output=True, text=True)
        if run.returncode != 0:
            lines.append(f"| {name} | {args.sigma:g} | – | failed: "
                         f"{(run.stderr.strip().splitlines() or ['?'])[-1][:150]} | | | | |")
            print(lines[-1], flush=True)
            continue
        r = json.loads(run.stdout.strip().splitlines()[-1])
        s = r["seconds"]
        faces = f"{r['faces']:,}"
        lines.append(
            f"| {name} | {args.sigma:g} | {faces} | {r['charts']} | {r['l2']:.4f} | "
            f"{s['load']:.1f}, {s['atlas']:.1f}, {s['bake']:.1f}, {s['save']:.1f}, "
            f"{s['read_back']:.1f} ({s['total']:.1f}) | {r['peak_mb']:.0f}, "
            f"{peak_step(r['peak_mb_after'])} | "
            f"{r['colour_difference_mean']:.2f} / {r['colour_difference_max']:.0f} |")
        print(lines[-1], flush=True)
    body = (f"pymeshlab 2025.07 in one process per mesh, texture {args.texture_size}² "
            "(`.venv/bin/python bench/scans_pymeshlab.py`; --big for the 5.5M and 13.7M "
            "meshes):\n\n" + "\n".join(lines) + "\n")
    (REPO / "bench" / "results" / "scans_pymeshlab.md").write_text(body)
    print(body)


if __name__ == "__main__":
    main()
