#!/usr/bin/env python3
"""One headless run of our filter in MeshLab 2022.02 or 2025.07 (no meshlabserver there), inside
the version's Debian root (scripts/make-meshlab-root.sh), and its check.

Copies meshlab_harness (built against that version), our plugin and the mesh into a fresh folder
in the root, then runs the harness there with chroot in a private mount namespace (the root gets
/proc only for that run): MeshLab's own plugin manager loads the root's plugins and ours, its own
importer reads the mesh, its own OBJ exporter writes the result.

  --expect success  exit 0, the OBJ has per-wedge UVs on every face, 0 flipped faces recomputed
                    from the file, the .mtl's texture exists, the file's L2 stretch matches the
                    filter's report (tests/meshlab/check_obj_uv.py);
  --expect refusal  the filter raised MLException with our one-line reason ("Parametrization:
                    Straightest Distances: <reason>" in MeshLab's log), the mesh is exactly as it
                    was before (the harness compares positions, faces, UVs, quality, textures),
                    and no file was written.
Output (harness log, OBJ) is kept in --out. Python standard library only.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

import debian_root

HERE = os.path.dirname(os.path.abspath(__file__))
SYSTEM_PLUGINS = "/usr/lib/x86_64-linux-gnu/meshlab/plugins"
FILTER_NAME = "Parametrization: Straightest Distances"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--root", required=True)
    parser.add_argument("--harness", required=True)
    parser.add_argument("--plugin", required=True,
                        help="our plugin, copied into the run's folder; or 'installed' (in the "
                        "root's system folder, from our Debian package) or 'absent' (must not be "
                        "loaded: the mesh is only opened and saved)")
    parser.add_argument("--mesh", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--expect", choices=("success", "refusal"), required=True)
    parser.add_argument("--max-l2", type=float)
    parser.add_argument("parameters", nargs="*", help="NAME=INT overrides of the defaults")
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    copied_plugin = args.plugin not in ("installed", "absent")
    for path in ([args.harness, args.mesh, os.path.join(root, SYSTEM_PLUGINS[1:])]
                 + ([args.plugin] if copied_plugin else [])):
        if not os.path.exists(path):
            print("FAIL: %s missing" % path)
            return 1

    inside = "/tmp/sdp-headless-%d" % os.getpid()
    folder = root + inside
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    try:
        shutil.copy2(args.harness, os.path.join(folder, "meshlab_harness"))
        for path in [args.mesh] + ([args.plugin] if copied_plugin else []):
            shutil.copy2(path, folder)
        plugin = inside + "/" + os.path.basename(args.plugin) if copied_plugin else args.plugin
        mesh = inside + "/" + os.path.basename(args.mesh)
        obj = inside + "/out.obj"
        # LD_LIBRARY_PATH: MeshLab's own edit plugins (2025.07) need libmeshlab-common-gui.so,
        # which the meshlab binary finds through its RUNPATH; a RUNPATH is not passed on to the
        # plugins the harness loads.
        env = {"HOME": inside, "QT_QPA_PLATFORM": "offscreen",
               "LD_LIBRARY_PATH": "/usr/lib/x86_64-linux-gnu/meshlab"}
        command = debian_root.command(
            root, [inside + "/meshlab_harness", SYSTEM_PLUGINS, plugin, mesh, obj] + args.parameters,
            env=env)
        result = subprocess.run(command, capture_output=True, text=True, timeout=600)
        output = result.stdout + result.stderr
        print(output)
        print("harness exit status: %d" % result.returncode)

        shutil.rmtree(args.out, ignore_errors=True)
        os.makedirs(args.out)
        log = os.path.join(args.out, "harness.log")
        with open(log, "w") as f:
            f.write(output)
        for name in os.listdir(folder):
            if name.startswith("out.") or name.endswith(".png"):
                shutil.copy2(os.path.join(folder, name), args.out)
        version = re.search(r"^meshlab (\S+) (float|double)$", output, re.M)
        if not version:
            print("FAIL: the harness did not start inside MeshLab")
            return 1
        print("PASS: running in MeshLab %s (%s)" % version.groups())

        if args.plugin == "absent":
            if result.returncode != 0 or "the filter is not loaded" not in output:
                print("FAIL: MeshLab did not open and save the mesh without our filter")
                return 1
            print("PASS: MeshLab opened and saved the mesh; our filter is not loaded")
            return 0
        if args.expect == "success":
            if result.returncode != 0:
                print("FAIL: the filter did not map the mesh and save it")
                return 1
            if "report flipped_faces 0" not in output:
                print("FAIL: the report does not say 0 flipped faces")
                return 1
            check = [sys.executable, os.path.join(HERE, "..", "meshlab", "check_obj_uv.py"),
                     os.path.join(args.out, "out.obj"), "--log", log]
            if args.max_l2 is not None:
                check += ["--max-l2", str(args.max_l2)]
            return subprocess.run(check).returncode

        if result.returncode == 4:
            print("FAIL: the filter refused but changed the mesh")
            return 1
        if result.returncode != 3:
            print("FAIL: expected a refusal (exit 3), got %d" % result.returncode)
            return 1
        reason = re.search(r"^log: .*%s: (.+)$" % re.escape(FILTER_NAME), output, re.M)
        refused = re.search(r"^refused: (.+)$", output, re.M)
        if not reason or not refused or reason.group(1).strip() != refused.group(1).strip():
            print("FAIL: no one-line reason in MeshLab's log matching the exception")
            return 1
        if any(name.startswith("out.") for name in os.listdir(folder)):
            print("FAIL: a file was written")
            return 1
        print("PASS: refused with the reason '%s', mesh untouched" % refused.group(1).strip())
        return 0
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
