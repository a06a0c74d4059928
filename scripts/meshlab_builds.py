#!/usr/bin/env python3
"""docs/meshlab.md's table of supported MeshLab builds and the README's install table, generated
from meshlab-builds.tsv (and the project's version in CMakeLists.txt).

  python3 scripts/meshlab_builds.py --check   fails, naming the block, when a file differs
  python3 scripts/meshlab_builds.py --write   rewrites the blocks between
                                              <!-- table:meshlab-builds --> (docs/meshlab.md),
                                              <!-- table:install --> (README.md) and their end
                                              markers
"""
import argparse
import pathlib
import re
import sys

from marked_block import update_block

REPO = pathlib.Path(__file__).resolve().parent.parent
BEGIN, END = "<!-- table:meshlab-builds -->\n", "<!-- /table:meshlab-builds -->"
INSTALL_BEGIN, INSTALL_END = "<!-- table:install -->\n", "<!-- /table:install -->"
COLUMNS = ["folder", "version", "api", "scalar", "runs_in", "tarball", "sha256", "deb",
           "root_extras", "users_get_it", "source"]
API_NAMES = {"mesh_filter_interface": "MeshFilterInterface", "filter_plugin": "FilterPlugin"}


def builds(table=REPO / "meshlab-builds.tsv"):
    rows = []
    for line in table.read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        fields = line.split("\t")
        if len(fields) != len(COLUMNS):
            sys.exit(f"meshlab_builds: {table}: {len(fields)} fields, want {len(COLUMNS)}: {line}")
        rows.append(dict(zip(COLUMNS, fields)))
    return rows


def tested_here(build):
    where = build["runs_in"]
    if where == "host":
        return ("yes, on this Debian 12: GUI under Xvfb (`tests/gui`) and meshlabserver "
                "(`tests/meshlab`, `tests/robustness`)")
    if where == "pymeshlab":
        return "yes, pytest inside real pymeshlab (`tests/python`)"
    if where.startswith("pymeshlab-"):
        return (f"yes, pytest inside real pymeshlab {where[len('pymeshlab-'):]} in a virtual "
                f"environment of its own (`.venv-{where}`), and the wheel beside it")
    return (f"yes, in a Debian {where} root (`scripts/make-meshlab-root.sh {where}`): GUI under "
            "Xvfb and the headless harness (`tests/meshlab_roots`)")


def package(build):
    if build["deb"] != "-":
        return f"`straightest-param-{build['deb']}` (.deb)"
    if build["runs_in"].startswith("pymeshlab"):
        return "`pymeshlab_straightest` (wheel)"
    return "–"


def markdown():
    lines = ["| MeshLab | where users get it | plugin API | precision | compiled against | "
             "plugin folder in `build/plugins/` | package | tested here |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for b in builds():
        source = (f"{b['source']} sources" if b["source"] == b["version"] else
                  f"{b['source']} sources, declaring {b['version']} (same plugin API; Debian has "
                  f"no {b['version']} source)")
        lines.append(f"| {b['version']} | {b['users_get_it']} | {API_NAMES[b['api']]} | "
                     f"{b['scalar']} | {source} | `{b['folder']}` | {package(b)} | "
                     f"{tested_here(b)} |")
    return "\n".join(lines) + "\n"


def project_version():
    found = re.search(r"project\(\S+ VERSION (\S+)", (REPO / "CMakeLists.txt").read_text())
    if not found:
        sys.exit("meshlab_builds: no project version in CMakeLists.txt")
    return found.group(1)


def install_markdown():
    """The README's table: one row per MeshLab build that has a Debian package (make-debs.sh)."""
    lines = ["| your MeshLab | where it comes from | command |", "| --- | --- | --- |"]
    for b in builds():
        if b["deb"] != "-":
            lines.append(f"| {b['version']} | {b['users_get_it']} | `apt install "
                         f"./straightest-param-{b['deb']}_{project_version()}_amd64.deb` |")
    return "\n".join(lines) + "\n"


def update(path, begin_marker, end_marker, generated, check):
    update_block(path, begin_marker, end_marker, generated, check,
                 f"meshlab_builds: the table {begin_marker.strip()} in {path} differs from "
                 "meshlab-builds.tsv; run python3 scripts/meshlab_builds.py --write")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--doc", default=str(REPO / "docs" / "meshlab.md"),
                        help="the file holding the builds table (default docs/meshlab.md)")
    parser.add_argument("--readme", default=str(REPO / "README.md"),
                        help="the file holding the install table (default README.md)")
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--check", action="store_true")
    mode.add_argument("--write", action="store_true")
    args = parser.parse_args()
    update(pathlib.Path(args.doc), BEGIN, END, markdown(), args.check)
    update(pathlib.Path(args.readme), INSTALL_BEGIN, INSTALL_END, install_markdown(), args.check)

if __name__ == "__main__":
    main()
