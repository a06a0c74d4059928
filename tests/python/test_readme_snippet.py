"""The pymeshlab snippet from a build (docs/pymeshlab.md), executed verbatim in a fresh
interpreter from a folder laid out like the repository (it names the default build folder build/
and resources/meshes/, as a reader's clone has them): the filter writes its checkerboard next to
the mesh, which must not land in the clone's resources/."""
import os
import re
import shutil
import subprocess
import sys

from conftest import PLUGIN, REPO


def test_readme_snippet_runs_verbatim(tmp_path):
    text = (REPO / "docs" / "pymeshlab.md").read_text()
    match = re.search(r"<!-- pymeshlab-snippet -->\n```python\n(.*?)```", text, re.S)
    assert match, "docs/pymeshlab.md has no pymeshlab snippet"
    plugin = tmp_path / "build/plugins/meshlab-2025.07/libfilter_straightest_param.so"
    plugin.parent.mkdir(parents=True)
    os.symlink(PLUGIN, plugin)
    (tmp_path / "resources/meshes/disk").mkdir(parents=True)
    shutil.copy(REPO / "resources/meshes/disk/nefertiti.off", tmp_path / "resources/meshes/disk")
    out = tmp_path / "out/nefertiti_pymeshlab.obj"
    done = subprocess.run([sys.executable, "-c", match.group(1)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "l2_stretch" in done.stdout and "flipped_faces" in done.stdout
    lines = out.read_text().splitlines()
    assert any(line.startswith("vt ") for line in lines)
    assert any(line.startswith("f ") and "/" in line for line in lines)
