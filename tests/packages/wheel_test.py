#!/usr/bin/env python3
"""The pip package as a pymeshlab user meets it. Run by the Python of a fresh virtual environment
where only `pip install pymeshlab_straightest-*.whl` ran (scripts/test-packages.sh makes it).

Checks:
  import   `import pymeshlab_straightest` binds
           MeshSet.compute_texcoord_parametrization_straightest_distances, and pymeshlab is the
           release asked for (--pymeshlab: 2025.7.post1 installed as the wheel's dependency, or
           an older one installed before it), whose own plugin was loaded;
  snippet  the README's package snippet (docs/pymeshlab.md holds the same), verbatim, in a folder
           holding a copy of the demo mesh: no load_plugin or bind lines, a report with 0 flipped
           faces, an OBJ with per-wedge UVs;
  notes    a quad mesh and a randomly wound one: the dict's `notes` name save_polygonal and
           the re-orienting filter, and save_current_mesh's defaults keep the texture
           coordinates on every (triangle) face;
  batch    50 meshes, good and bad mixed (a fixed shuffle), each loaded from a file into a new
           MeshSet and filtered in one process, catching the refusals, as a batch script does
           (pymeshlab 2025.7 crashes such a loop by itself: see the package's docstring). Run in
           a child process so that a crash is seen as one: it must exit 0, every bad mesh must
           raise with its own one-line reason, every good mesh must map with 0 flipped faces
           (signed UV area of every face from the wedge UVs pymeshlab hands back).
"""
import argparse
import json
import os
import pathlib
import random
import re
import shutil
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parents[1]
sys.path.insert(0, str(REPO / "tests" / "robustness"))
import meshgen  # noqa: E402

# Flattened by the filter (tests/robustness/CASES.md), and refused with meshgen's reason.
GOOD_CASES = ["wavy", "annulus", "two_holes", "quads", "needles", "one_triangle",
              "no_interior_vertex", "offset_1e6"]
BAD_CASES = ["closed", "two_components", "bowtie", "nonmanifold_edge", "nonmanifold_vertex",
             "inconsistent_orientation"]

BATCH = r'''
import json, sys
import numpy as np
import pymeshlab
import pymeshlab_straightest  # noqa: F401

results = []
for path in json.loads(sys.argv[1]):
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(path)
    try:
        report = ms.compute_texcoord_parametrization_straightest_distances(
            texturename="batch_checker.png")
    except pymeshlab.PyMeshLabException as error:
        results.append({"path": path, "refused": str(error).strip().splitlines()[-1]})
        continue
    uv = ms.current_mesh().wedge_tex_coord_matrix().reshape(-1, 3, 2)
    e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    areas = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    results.append({"path": path, "report_flipped": int(report["flipped_faces"]),
                    "uv_flipped": int((areas <= 0).sum()), "faces": len(areas)})
    print(len(results), path, "mapped", flush=True)
print(json.dumps(results))
'''


def check(condition, message):
    if not condition:
        print("FAIL: " + message)
        sys.exit(1)
    print("PASS: " + message, flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--wheel", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--pymeshlab", default="2025.7.post1",
                        help="the pymeshlab release the environment holds")
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)

    # --- import ---------------------------------------------------------------------------
    import importlib.metadata as metadata
    import pymeshlab
    import pymeshlab_straightest

    check(metadata.version("pymeshlab") == args.pymeshlab,
          "pymeshlab %s is installed beside the wheel" % metadata.version("pymeshlab"))
    check(pathlib.Path(pymeshlab_straightest.PLUGIN_PATH).parent.name == args.pymeshlab,
          "the plugin loaded is the one built for it: %s" % pymeshlab_straightest.PLUGIN_PATH)
    check(pathlib.Path(pymeshlab_straightest.__file__).resolve().parents[1]
          != REPO / "python", "pymeshlab_straightest is the installed one, not the source folder")
    check(callable(getattr(pymeshlab.MeshSet, pymeshlab_straightest.FILTER_NAME, None)),
          "import pymeshlab_straightest binds MeshSet.%s" % pymeshlab_straightest.FILTER_NAME)

    # A release it has no plugin for is refused at import, with the releases it serves.
    refusal = subprocess.run([sys.executable, "-c", (
        "import importlib.metadata as m\n"
        "real = m.version\n"
        "m.version = lambda name: '2024.1' if name == 'pymeshlab' else real(name)\n"
        "import pymeshlab_straightest\n")], capture_output=True, text=True, timeout=120)
    last = (refusal.stderr.strip().splitlines() or [""])[-1]
    check(refusal.returncode != 0 and "ImportError" in last and "pymeshlab 2024.1 is not served"
          in last and "2022.2.post4" in last, "another pymeshlab release is refused at import: "
          + last)

    # --- the README snippet -----------------------------------------------------------------
    pattern = r"<!-- pip-package-snippet -->\n```python\n(.*?)```"
    match = re.search(pattern, (REPO / "README.md").read_text(), re.S)
    check(match is not None, "README has the package snippet")
    snippet = match.group(1)
    copy = re.search(pattern, (REPO / "docs" / "pymeshlab.md").read_text(), re.S)
    check(copy is not None and copy.group(1) == snippet,
          "docs/pymeshlab.md has the same package snippet")
    check("load_plugin" not in snippet and "bind_function" not in snippet,
          "the snippet has no load_plugin/bind_function lines")
    folder = out / "snippet"
    folder.mkdir()
    shutil.copy(REPO / "resources" / "meshes" / "disk" / "nefertiti.off", folder)
    done = subprocess.run([sys.executable, "-c", snippet], cwd=folder, capture_output=True,
                          text=True, timeout=300)
    print(done.stdout + done.stderr)
    check(done.returncode == 0 and "'flipped_faces': 0" in done.stdout,
          "the snippet runs verbatim and reports 0 flipped faces")
    objs = list(folder.glob("*.obj"))
    check(len(objs) == 1 and any(line.startswith("vt ") for line in objs[0].read_text().split("\n")),
          "the snippet saved an OBJ with texture coordinates")

    # --- notes: a quad torus wound at random saved with pymeshlab's defaults ----------------
    folder = out / "notes"
    folder.mkdir()
    for name in ("torus_quads.off", "torus_random_winding.off"):
        shutil.copy(REPO / "resources" / "meshes" / "inputs" / name, folder)
        ms = pymeshlab.MeshSet()
        ms.load_new_mesh(str(folder / name))
        report = ms.compute_texcoord_parametrization_straightest_distances_atlas(texturesize=512)
        check(isinstance(report.get("notes"), list), "%s: the dict has `notes`" % name)
        polygonal = name == "torus_quads.off"
        check(any("save_polygonal" in note for note in report["notes"]) == polygonal,
              "%s: the notes name save_polygonal only for the polygon mesh" % name)
        check(any("meshing_re_orient_faces_coherently" in note for note in report["notes"])
              != polygonal, "%s: the notes name the re-orienting filter only when faces were "
              "wound against their neighbours" % name)
        ms.save_current_mesh(str(folder / (name + ".obj")))
        faces = [line.split() for line in (folder / (name + ".obj")).read_text().split("\n")
                 if line.startswith("f ")]
        check(faces and all(len(f) == 4 and all(c.count("/") >= 1 and c.split("/")[1]
                                                for c in f[1:]) for f in faces),
              "%s: saved with the defaults, every face a triangle with texture coordinates" % name)

    # --- the batch ----------------------------------------------------------------------------
    meshes = out / "batch"
    meshes.mkdir()
    expected = {}  # path -> the reason it must be refused with, None for a good mesh
    for i in range(50):
        pool = GOOD_CASES if i % 2 == 0 else BAD_CASES
        name = pool[(i // 2) % len(pool)]
        path = meshgen.write_off(str(meshes / ("%02d_%s.off" % (i, name))), meshgen.CASES[name]())
        expected[path] = meshgen.REFUSED_REASONS[name] if name in BAD_CASES else None
    paths = sorted(expected)
    random.Random(1).shuffle(paths)
    run = subprocess.run([sys.executable, "-c", BATCH, json.dumps(paths)], capture_output=True,
                         text=True, timeout=900, cwd=meshes)
    (out / "batch.log").write_text(run.stdout + run.stderr)
    check(run.returncode == 0, "a batch of 50 meshes, %d bad, in one process: no crash (exit %d)"
          % (sum(1 for r in expected.values() if r), run.returncode))
    results = json.loads(run.stdout.strip().splitlines()[-1])
    check(len(results) == 50, "all 50 meshes were handled")
    for result in results:
        reason = expected[result["path"]]
        name = os.path.basename(result["path"])
        if reason:
            check(result.get("refused", "").endswith(reason),
                  "%s raised with its reason: %s" % (name, result.get("refused")))
        else:
            check("refused" not in result and result["report_flipped"] == 0
                  and result["uv_flipped"] == 0,
                  "%s mapped, 0 flipped of %s faces" % (name, result.get("faces")))
    print("PASSED")


if __name__ == "__main__":
    main()
