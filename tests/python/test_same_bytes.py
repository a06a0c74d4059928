"""The filter's default map is the same bytes on every run inside pymeshlab too: three fresh
processes (quiet, beside a CPU hog, on one core) run it with its defaults on a generated 58k-vertex
bumpy patch, where the work budget ends the refinement, and save PLY and OBJ with wedge UVs;
the files must be identical byte for byte (tests/cli/same_bytes.py does the same for the CLI)."""
import json
import subprocess
import sys

import pytest

from conftest import FILTER, PLUGIN, REPO

sys.path.insert(0, str(REPO / "tests" / "cli"))
from same_bytes import bumpy_patch, cpu_hog  # noqa: E402

CHILD = """
import json, sys
import pymeshlab
plugin, mesh, folder, name = sys.argv[1:5]
if name not in pymeshlab.filter_list():
    pymeshlab.load_plugin(plugin)
ms = pymeshlab.MeshSet()
ms.load_new_mesh(mesh)
report = getattr(ms, "apply_filter")(name)
for extension in ("ply", "obj"):
    ms.save_current_mesh(f"{folder}/map.{extension}", save_wedge_texcoord=True)
print(json.dumps({k: report[k] for k in ("l2_stretch", "flipped_faces")}))
"""


def run(mesh, folder, prefix=()):
    folder.mkdir()
    done = subprocess.run([*prefix, sys.executable, "-c", CHILD, str(PLUGIN), str(mesh),
                           str(folder), FILTER], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["flipped_faces"] == 0
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir())}


def test_default_map_is_the_same_bytes_quiet_loaded_and_on_one_core(tmp_path):
    if not PLUGIN.exists():
        pytest.skip(f"plugin {PLUGIN} not built")
    mesh = bumpy_patch(tmp_path / "bumps.off")
    quiet = run(mesh, tmp_path / "quiet")
    with cpu_hog():
        loaded = run(mesh, tmp_path / "hog")
    one_core = run(mesh, tmp_path / "one_core", prefix=["taskset", "-c", "0"])
    assert {"map.ply", "map.obj"} <= quiet.keys()
    for name, files in (("beside a CPU hog", loaded), ("on one core", one_core)):
        assert files.keys() == quiet.keys(), name
        for file in quiet:
            assert files[file] == quiet[file], f"{name}: {file} differs from the quiet run's"
