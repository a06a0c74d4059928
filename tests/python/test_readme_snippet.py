"""The README's pymeshlab snippet, executed verbatim in a fresh interpreter from the repository
folder (it names the default build folder build/ and ../shared, as a reader's clone has them)."""
import re
import subprocess
import sys

from conftest import REPO


def test_readme_snippet_runs_verbatim():
    text = (REPO / "README.md").read_text()
    match = re.search(r"<!-- pymeshlab-snippet -->\n```python\n(.*?)```", text, re.S)
    assert match, "README has no pymeshlab snippet"
    out = REPO / "out/nefertiti_pymeshlab.obj"
    if out.exists():
        out.unlink()
    done = subprocess.run([sys.executable, "-c", match.group(1)], cwd=REPO, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "l2_stretch" in done.stdout and "flipped_faces" in done.stdout
    lines = out.read_text().splitlines()
    assert any(line.startswith("vt ") for line in lines)
    assert any(line.startswith("f ") and "/" in line for line in lines)
