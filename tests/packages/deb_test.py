#!/usr/bin/env python3
"""A Debian package of ours as a user meets it: `apt-get install ./<deb>`, a run of the installed
filter in that MeshLab and of the installed command line tool, then `apt-get remove`, after which
MeshLab still works.

Where:
  --root DIR  a Debian root with that MeshLab (scripts/make-meshlab-root.sh: trixie for 2022.02,
              sid for 2025.07), entered with chroot in a private mount namespace; the filter runs
              through tests/meshlab_roots/headless_case.py (the version's own plugin loader, which
              finds the installed plugin in its system folder);
  no --root   this machine (Debian 12, MeshLab 2020.09): the filter runs in the system
              meshlabserver with the installed example script, under xvfb-run. A package left
              installed by a failed run is removed first, and at the end whatever happens.

Checks: the package installs with apt-get, puts the plugin into MeshLab's plugin folder,
straightest_param into /usr/bin and the .mlx and docs under /usr/share (every relative link of
the installed Markdown files resolving inside their doc folder); the installed filter maps
a disk (0 flipped faces recomputed from the saved OBJ) and the installed CLI does too; after
`apt-get remove` the files are gone and MeshLab opens and saves a mesh without our filter.
"""
import argparse
import importlib.util
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CHECK_OBJ = os.path.join(HERE, "..", "meshlab", "check_obj_uv.py")
HEADLESS = os.path.join(HERE, "..", "meshlab_roots", "headless_case.py")
sys.path.insert(0, os.path.join(HERE, "..", "meshlab_roots"))
import debian_root  # noqa: E402

# scripts/check-links.py (its name has a hyphen, so it is loaded from its path).
_spec = importlib.util.spec_from_file_location(
    "check_links", os.path.join(HERE, "..", "..", "scripts", "check-links.py"))
check_links = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(check_links)

PLUGIN = "/usr/lib/x86_64-linux-gnu/meshlab/plugins/libfilter_straightest_param.so"
FILES = [PLUGIN, "/usr/bin/straightest_param", "/usr/share/straightest_param/straightest_param.mlx"]


class Failed(Exception):
    pass


def run(command, **kwargs):
    print("$ " + " ".join(command), flush=True)
    result = subprocess.run(command, capture_output=True, text=True, **kwargs)
    print(result.stdout + result.stderr, flush=True)
    return result


class Target:
    """This machine, or a Debian root entered with chroot (commands get /proc there)."""

    def __init__(self, root):
        self.root = root

    def path(self, inside):  # a path on the target, seen from here
        return (self.root or "") + inside

    def run(self, *command, env=None):
        if not self.root:
            return run(list(command), env=dict(os.environ, **(env or {})))
        return run(debian_root.command(self.root, command,
                                       env=dict(DEBIAN_FRONTEND="noninteractive", **(env or {}))))

    def installed(self, package):
        result = self.run("dpkg-query", "-W", "-f=${Status}", package)
        return result.returncode == 0 and "install ok installed" in result.stdout


def check(condition, message):
    if not condition:
        raise Failed(message)
    print("PASS: " + message, flush=True)


def test(args, target, folder):
    package = os.path.basename(args.deb).split("_")[0]
    deb = folder + "/" + os.path.basename(args.deb)
    shutil.copy2(args.deb, target.path(deb))
    for name in (args.mesh, args.bad_mesh):
        shutil.copy2(name, target.path(folder))
    mesh = folder + "/" + os.path.basename(args.mesh)

    if target.installed(package):  # left by a killed run
        target.run("apt-get", "remove", "-y", package)
    result = target.run("apt-get", "install", "-y", "--no-install-recommends", deb)
    check(result.returncode == 0 and target.installed(package),
          "apt-get install ./%s" % os.path.basename(args.deb))
    missing = [f for f in FILES if not os.path.exists(target.path(f))]
    check(not missing, "installed %s" % ", ".join(FILES) + (" (missing %s)" % missing if missing else ""))
    docs = target.path("/usr/share/doc/%s" % package)
    check(os.path.isfile(os.path.join(docs, "README.md")) and
          os.path.isfile(os.path.join(docs, "copyright")), "docs in /usr/share/doc/%s" % package)
    # The README and every Markdown file shipped beside it (docs/, the bench results they
    # link to): each link resolves inside the doc folder.
    installed_md = sorted(os.path.join(top, name) for top, _, names in os.walk(docs)
                          for name in names if name.endswith(".md"))
    broken = [(os.path.relpath(md, docs),) + b for md in installed_md
              for b in check_links.broken(md, inside=docs)]
    check(len(installed_md) > 1 and not broken,
          "every relative link of the %d installed Markdown files resolves in /usr/share/doc/%s"
          % (len(installed_md), package) + "".join("\n  %s:%d: %s: %s" % b for b in broken))

    # The installed command line tool.
    cli_out = folder + "/cli.obj"
    result = target.run("/usr/bin/straightest_param", mesh, cli_out, "--quiet")
    check(result.returncode == 0, "the installed straightest_param maps %s" % os.path.basename(mesh))
    check(subprocess.run([sys.executable, CHECK_OBJ, target.path(cli_out)]).returncode == 0,
          "its OBJ has per-wedge UVs, 0 flipped faces")

    # The installed filter, in that MeshLab.
    if target.root:
        for mesh_file, expect in ((args.mesh, "success"), (args.bad_mesh, "refusal")):
            result = run([sys.executable, HEADLESS, "--root", target.root, "--harness",
                          args.harness, "--plugin", "installed", "--mesh", mesh_file,
                          "--out", os.path.join(args.out, "installed_" + expect),
                          "--expect", expect])
            check(result.returncode == 0, "the installed filter in MeshLab %s: %s" %
                  (args.meshlab_version, expect))
    else:
        obj = folder + "/meshlabserver.obj"
        result = run(["xvfb-run", "-a", "-s", "-screen 0 1024x768x24", "/usr/bin/meshlabserver",
                      "-i", mesh, "-o", obj, "-m", "wt", "-s",
                      "/usr/share/straightest_param/straightest_param.mlx"])
        log = os.path.join(args.out, "meshlabserver.log")
        with open(log, "w") as f:
            f.write(result.stdout + result.stderr)
        check(result.returncode == 0, "the installed filter in the system meshlabserver 2020.09")
        check(subprocess.run([sys.executable, CHECK_OBJ, obj, "--log", log]).returncode == 0,
              "its OBJ has per-wedge UVs, 0 flipped faces, the logged L2")

    result = target.run("apt-get", "remove", "-y", package)
    check(result.returncode == 0 and not target.installed(package), "apt-get remove %s" % package)
    left = [f for f in FILES if os.path.exists(target.path(f))]
    check(not left, "the package's files are gone" + (" (left: %s)" % left if left else ""))

    # MeshLab still works without us.
    if target.root:
        result = run([sys.executable, HEADLESS, "--root", target.root, "--harness", args.harness,
                      "--plugin", "absent", "--mesh", args.mesh,
                      "--out", os.path.join(args.out, "removed"), "--expect", "success"])
        check(result.returncode == 0, "MeshLab %s opens and saves a mesh after the removal"
              % args.meshlab_version)
    else:
        ply = folder + "/plain.ply"
        result = run(["xvfb-run", "-a", "-s", "-screen 0 1024x768x24", "/usr/bin/meshlabserver",
                      "-i", mesh, "-o", ply])
        check(result.returncode == 0 and os.path.isfile(ply),
              "meshlabserver opens and saves a mesh after the removal")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--deb", required=True)
    parser.add_argument("--meshlab-version", required=True)
    parser.add_argument("--mesh", required=True, help="a disk-shaped .off")
    parser.add_argument("--bad-mesh", required=True, help="a mesh the filter refuses")
    parser.add_argument("--out", required=True)
    parser.add_argument("--root")
    parser.add_argument("--harness", help="meshlab_harness of that version (with --root)")
    args = parser.parse_args()
    if args.root and not args.harness:
        parser.error("--root needs --harness")
    if os.geteuid() != 0:
        print("FAIL: installing a package needs root")
        return 1
    os.makedirs(args.out, exist_ok=True)
    target = Target(os.path.abspath(args.root) if args.root else None)
    folder = "/tmp/sdp-deb-test-%d" % os.getpid()
    os.makedirs(target.path(folder))
    package = os.path.basename(args.deb).split("_")[0]
    try:
        test(args, target, folder)
    except Failed as e:
        print("FAIL: " + str(e))
        return 1
    finally:
        if target.installed(package):
            target.run("apt-get", "remove", "-y", package)
        shutil.rmtree(target.path(folder), ignore_errors=True)
    print("PASSED")
    return 0


if __name__ == "__main__":
    sys.exit(main())
