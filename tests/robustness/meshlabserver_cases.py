#!/usr/bin/env python3
"""The robustness cases (tests/robustness/CASES.md) through MeshLab 2020.09's meshlabserver with
our plugin (a private prefix made by scripts/make-meshlab-prefix.sh), under Xvfb.

usage: meshlabserver_cases.py --prefix PREFIX --mlx straightest_param.mlx --workdir DIR CASE

Like tests/meshlab/meshlabserver_case.sh, but a case may change the filter's parameters, run
MeshLab filters before ours (selection, deleting faces) and name the exact reason it expects.
  refused: meshlabserver exits non-zero, writes no output, prints our log line
           "Parametrization: Straightest Distances: <reason>" with the expected reason, and the
           input file is unchanged.
  flattened: exit 0, our report line in the log, and the OBJ written by meshlabserver has
           per-wedge UVs with positive area on every flattened face (recomputed from the file);
           where positions survive the OBJ's 6 decimals, the log's L2 equals the file's.
"""
import argparse
import hashlib
import math
import os
import re
import shutil
import signal
import subprocess
import sys
from xml.sax.saxutils import quoteattr

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "meshlab"))
import meshgen  # noqa: E402
from meshgen import check  # noqa: E402
from check_obj_uv import read_obj, sander_stretch  # noqa: E402

FILTER = "Parametrization: Straightest Distances"


def select_faces(condition):
    """MeshLab's Conditional Face Selection (muparser over x0..z2, fi)."""
    return (f'<filter name="Conditional Face Selection">'
            f'<Param type="RichString" name="condSelect" value={quoteattr(condition)}/></filter>')


SELECT_NONE = ('<filter name="Select None"><Param type="RichBool" name="allFaces" value="true"/>'
               '<Param type="RichBool" name="allVerts" value="true"/></filter>')
DELETE_FACES = '<filter name="Delete Selected Faces"/>'
DELETE_FACES_AND_VERTICES = '<filter name="Delete Selected Faces and Vertices"/>'


class Server:
    def __init__(self, prefix, mlx, workdir):
        self.prefix = prefix
        with open(mlx) as f:
            text = f.read()
        self.filter_xml = re.search(r'<filter name="%s">.*?</filter>' % re.escape(FILTER), text,
                                    re.S).group(0)
        self.workdir = workdir
        shutil.rmtree(workdir, ignore_errors=True)
        os.makedirs(workdir)
        self.runs = 0

    def script(self, params=None, before=()):
        xml = self.filter_xml
        for name, value in (params or {}).items():
            xml, count = re.subn(r'(name="%s" value=")[^"]*"' % name, r'\g<1>%s"' % value, xml)
            check(count == 1, f"cannot set parameter {name}")
        return "<!DOCTYPE FilterScript>\n<FilterScript>\n" + "\n".join(list(before) + [xml]) + \
            "\n</FilterScript>\n"

    def run(self, mesh_text_or_path, params=None, before=(), name="in.off", memory_kb=None,
            link=False):
        """One meshlabserver run in a fresh folder; returns (status, log, folder, output).
        With memory_kb, under `ulimit -v` and with line-buffered output (so the log shows how far
        a run got even when it aborts)."""
        self.runs += 1
        folder = os.path.join(self.workdir, f"run{self.runs}")
        os.makedirs(folder)
        input_path = os.path.join(folder, name)
        if link:  # a large file: a symbolic link, the filter writes its texture beside it
            os.symlink(os.path.abspath(mesh_text_or_path), input_path)
        elif os.path.isfile(str(mesh_text_or_path)):
            shutil.copy(mesh_text_or_path, input_path)
        else:
            with open(input_path, "wb") as f:
                f.write(mesh_text_or_path if isinstance(mesh_text_or_path, bytes)
                        else mesh_text_or_path.encode())
        digest = sha256(input_path)
        script_path = os.path.join(folder, "script.mlx")
        with open(script_path, "w") as f:
            f.write(self.script(params, before))
        output = os.path.join(folder, "out.obj")
        server = [os.path.join(self.prefix, "bin", "meshlabserver"),
                  "-i", input_path, "-o", output, "-m", "wt", "-s", script_path]
        if memory_kb is not None:
            server = ["bash", "-c", f'ulimit -v {memory_kb}; exec stdbuf -oL -eL "$0" "$@"'] + server
        # Under a memory limit MeshLab itself can stall before our filter runs (Qt waits forever
        # for a thread it could not start while a system plugin loads): such a run is stopped,
        # whole process group, and reported with status None ("not counted" by the caller).
        process = subprocess.Popen(
            ["xvfb-run", "-a", "-s", "-screen 0 1024x768x24"] + server,
            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
            start_new_session=True)
        try:
            stdout, _ = process.communicate(timeout=240 if memory_kb is None else 60)
            returncode = process.returncode
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            stdout, _ = process.communicate()
            returncode = None
        done = subprocess.CompletedProcess(process.args, returncode, stdout)
        log = done.stdout.decode(errors="replace")
        with open(os.path.join(folder, "meshlabserver.log"), "w") as f:
            f.write(log)
        print(log)
        print(f"meshlabserver exit status: {done.returncode}")
        check(sha256(input_path) == digest, "meshlabserver changed the input file")
        return done.returncode, log, folder, output

    # --- the two contracts -----------------------------------------------------------------------

    def refused(self, mesh, reason, params=None, before=(), exact=True, loader=False):
        status, log, folder, output = self.run(mesh, params, before)
        check(status != 0, "meshlabserver succeeded")
        check(status not in (134, 139, -6, -11), f"meshlabserver crashed (status {status})")
        check(not os.path.exists(output), "an output file was written")
        if loader:  # MeshLab's importer refuses the file before any filter runs
            check("Failed loading" in log, "no loader message in the log")
            print("PASS: refused by MeshLab's loader")
            return
        found = re.findall(r"^%s: (.+)$" % re.escape(FILTER), log, re.M)
        check(found, "the filter's reason is not in the log")
        got = found[0].strip()
        check(got == reason if exact else reason in got, f"reason {got!r}, expected {reason!r}")
        check("Straightest distances:" not in log, "a report line was logged for a failed run")
        print(f"PASS: refused: {got}")

    def flattened(self, mesh, params=None, before=(), faces=None, warnings=(),
                  compare_l2=True, flattened_face=None, log_counts=None):
        """Returns (log L2, log flipped, OBJ faces, OBJ uv per face)."""
        status, log, folder, output = self.run(mesh, params, before)
        check(status == 0, f"meshlabserver failed with status {status}")
        check(os.path.isfile(output), "no output file")
        check(re.search(r"^Straightest distances: ", log, re.M), "no report line in the log")
        if log_counts is not None:
            check(f"Straightest distances: {log_counts[0]} vertices, {log_counts[1]} faces" in log,
                  f"the report line does not say {log_counts[0]} vertices, {log_counts[1]} faces")
        for warning in warnings:
            check(f"warning: {warning}" in log, f"warning {warning!r} not in the log")
        l2, flipped = re.findall(r"L2 stretch (\S+), Linf stretch \S+, flipped faces (\d+)", log)[-1]
        positions, uvs, obj_faces, _ = read_obj(output)
        if faces is not None:
            check(len(obj_faces) == faces, f"{len(obj_faces)} faces written, expected {faces}")
        bad, triangles = [], []
        for k, corners in enumerate(obj_faces):
            q = [positions[v - 1] for v, _ in corners]
            if flattened_face is not None and not flattened_face(q):
                continue
            check(len(corners) == 3 and all(vt is not None for _, vt in corners),
                  f"face {k} has no per-wedge texture coordinates")
            p = [uvs[vt - 1] for _, vt in corners]
            (s1, t1), (s2, t2), (s3, t3) = p
            if (s2 - s1) * (t3 - t1) - (s3 - s1) * (t2 - t1) <= 0:
                bad.append(k)
            triangles.append((q, p))
        if int(flipped) == 0:
            check(not bad, f"{len(bad)} faces with non-positive UV area in the OBJ: {bad[:10]}")
        if compare_l2 and not bad:
            file_l2, _ = sander_stretch(triangles)
            check(math.isclose(file_l2, float(l2), rel_tol=2e-3),
                  f"logged L2 {l2} != the file's {file_l2:.6f}")
        print(f"PASS: flattened, L2 {l2}, flipped {flipped}, {len(obj_faces)} faces")
        return float(l2), int(flipped), bad


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def off(name, mesh=None):
    return meshgen.off_text(mesh if mesh is not None else meshgen.CASES[name]())


REFUSED = {name: meshgen.REFUSED_REASONS[name] for name in (
    "closed", "two_components", "triangle_soup", "nonmanifold_edge", "nonmanifold_vertex",
    "duplicate_face", "inconsistent_orientation", "nan_vertex", "inf_vertex")}

FLATTENED = {  # case: (faces in the output, warnings)
    "annulus": (24, ()),
    "two_holes": (124, ()),
    "quads": (32, ()),
    "zero_area": (128, ("4 vertices with a degenerate 1-ring used uniform weights",)),
    "needles": (288, ()),
    "duplicate_vertex_unused": (72, ()),
    "duplicate_vertex_seam": (128, ()),
    "unreferenced_vertices": (72, ()),
    "one_triangle": (1, ("the patch has no interior vertex to measure the boundary from; used the "
                         "circle boundary instead",)),
    "no_interior_vertex": (10, ("the patch has no interior vertex to measure the boundary from; "
                                "used the circle boundary instead",)),
}


def in_region(q):
    """Faces whose three corners have x < 0.55: a disk-shaped part of the 8 x 8 wavy grid."""
    return all(p[0] < 0.55 for p in q)


def case_needle_edge(server):
    """A 1e-7 short edge: one-to-one in double precision, but MeshLab stores UVs as floats and
    its OBJ as 6 decimals, where the two needle faces would collapse. The core repairs the map as
    stored: the saved OBJ has no flipped face and the log says what was moved, with no warning
    that faces are degenerate."""
    n = 8
    V, F = meshgen.wavy(n)
    v, w = meshgen.grid_index(n, 4, 4), meshgen.grid_index(n, 5, 4)
    V[v] = tuple(p + (q - p) * (1 - 1e-7) for p, q in zip(V[v], V[w]))
    _, flipped, bad = server.flattened(off("", (V, F)), faces=128, compare_l2=False)
    check(flipped == 0 and not bad, f"{flipped} flipped faces in the saved OBJ: {bad}")
    status_log = open(os.path.join(server.workdir, "run1", "meshlabserver.log")).read()
    check("degenerate" not in status_log, "a degenerate-face warning in the log")
    check(re.search(r"LOG: \d+ stored one-to-one: 2 faces would have collapsed when rounded to "
                    r"float, 6 decimals texture coordinates; \d+ vertices moved", status_log),
          "no line about the repaired faces in the log")


def case_scaled(server, name, tolerance):
    base, _, _ = server.flattened(off("wavy"), faces=128)
    # The OBJ exporter keeps 6 decimals: positions of a mesh scaled by 1e-6 do not survive it, so
    # the file's L2 cannot be recomputed there; the UVs (in [0, 1]) do.
    l2, _, _ = server.flattened(off(name), faces=128, compare_l2=(name != "scaled_1e-6"))
    check(abs(l2 - base) <= tolerance * base, f"L2 {l2} vs {base} without {name}")


def case_deleted(server, delete):
    """The faces around the centre vertex deleted by MeshLab, with or without that vertex: MeshLab
    2020.09 only flags them deleted (the containers keep them, indices unchanged). The result
    equals the run on the same mesh written without them."""
    n = 8
    V, F = meshgen.wavy(n)
    centre = meshgen.grid_index(n, 4, 4)
    near = " || ".join(f"((x{k} - 0.5)^2 + (y{k} - 0.5)^2 < 1e-4)" for k in range(3))
    kept = [f for f in F if centre not in f]
    l2, _, _ = server.flattened(off("wavy"), before=[select_faces(near), delete], faces=len(kept),
                                log_counts=(80, len(kept)))
    log = open(os.path.join(server.workdir, "run1", "meshlabserver.log")).read()
    deleted_vertices = 1 if delete == DELETE_FACES_AND_VERTICES else 0
    check(f"Deleted {len(F) - len(kept)} faces" in log and
          (deleted_vertices == 0 or f"{deleted_vertices} vertices" in log),
          "MeshLab did not delete what the case needs")
    expected, _, _ = server.flattened(off("", (V, kept)), faces=len(kept), log_counts=(80, len(kept)))
    check(l2 == expected, f"L2 {l2} with deleted elements, {expected} without")


def case_selected_disk(server):
    """Only the selected faces (a disk) are flattened; the result equals that part on its own."""
    V, F = meshgen.wavy(8)
    condition = "(x0 < 0.55) && (x1 < 0.55) && (x2 < 0.55)"
    l2, _, _ = server.flattened(off("wavy"), params={"selectedonly": "true"},
                                before=[select_faces(condition)], faces=128,
                                flattened_face=in_region, compare_l2=True)
    part = [f for f in F if in_region([V[v] for v in f])]
    expected, _, _ = server.flattened(off("", (V, part)), faces=len(part))
    check(l2 == expected, f"L2 {l2} of the selection, {expected} of the part alone")


def case_out_of_memory(server, big):
    """A mesh too large for memory: meshlabserver under `ulimit -v` from 60 % to 106 % of what it
    needs without a limit. Below some limit MeshLab 2020.09 itself cannot start or load the mesh
    (aborts in Qt's plugin loader, "Failed loading"): those runs never reach our filter and are
    not counted. Once our filter has started ("straightest distances: topology" in the log),
    each run must succeed or be refused with a reason naming memory; never abort."""
    folder = os.path.join(server.workdir, "unlimited")
    os.makedirs(folder)
    os.symlink(os.path.abspath(big), os.path.join(folder, "in.off"))
    with open(os.path.join(folder, "script.mlx"), "w") as f:
        f.write(server.script({"texturesize": "16"}))
    # The peak virtual memory of an unlimited run (VmPeak sampled until it exits): what the
    # server needs on this machine (OpenMP threads and malloc arenas grow with the cores).
    done = subprocess.run(
        ["xvfb-run", "-a", "-s", "-screen 0 1024x768x24", "bash", "-c",
         'exec "$0" "$@" >server.log 2>&1 & pid=$!; peak=0; while kill -0 $pid 2>/dev/null; do '
         'v=$(awk \'/VmPeak/ {print $2}\' /proc/$pid/status 2>/dev/null); '
         '[ -n "$v" ] && [ "$v" -gt "$peak" ] && peak=$v; sleep 0.05; done; '
         'wait $pid; s=$?; echo $peak > peak.txt; exit $s',
         os.path.join(server.prefix, "bin", "meshlabserver"), "-i", "in.off", "-o", "out.obj",
         "-m", "wt", "-s", "script.mlx"], cwd=folder, stdin=subprocess.DEVNULL, timeout=300)
    check(done.returncode == 0, f"the unlimited run failed ({done.returncode})")
    with open(os.path.join(folder, "peak.txt")) as f:
        peak = int(f.read().split()[0])
    check(peak > 0, "could not measure the peak virtual memory")
    print(f"unlimited run: meshlabserver VmPeak {peak >> 10} MB")
    # Coarse below, fine near the peak, where the solver's big arrays are allocated.
    fractions = [0.70, 0.80, 0.86, 0.89, 0.92, 0.95, 0.98]
    outcomes = []
    for fraction in fractions:
        limit_kb = int(peak * fraction)
        status, log, _, output = server.run(big, params={"texturesize": "16"},
                                            memory_kb=limit_kb, link=True)
        started = "straightest distances: topology" in log  # its first progress line
        reason = re.findall(r"^%s: (.+)$" % re.escape(FILTER), log, re.M)
        problem = None
        if reason:
            outcome = "refused: " + reason[0]
            if status == 0 or "memory" not in reason[0] or os.path.exists(output):
                problem = "the reason does not name memory, or the run went on"
        elif not started:  # MeshLab could not start, load the mesh or load our plugin
            outcome = (f"MeshLab stopped before our filter (status {status}; not counted)"
                       if status is not None else
                       "MeshLab stalled before our filter (stopped after 60 s; not counted)")
        elif status == 0:
            outcome = "success"
            if not os.path.isfile(output):
                problem = "no output file"
        else:
            outcome = f"status {status}"
            last = [line for line in log.splitlines() if line.strip()][-3:]
            problem = "our filter started and the run ended without its reason: " + \
                " | ".join(last)
        outcomes.append((limit_kb >> 10, started, problem, outcome))
    for limit_mb, started, problem, outcome in outcomes:
        print(f"  {limit_mb} MB: {'PROBLEM: ' + problem + ': ' if problem else ''}{outcome}")
    problems = [o for o in outcomes if o[2]]
    check(not problems, f"{len(problems)} limits broke the contract: " +
          "; ".join(f"{mb} MB: {p} ({o})" for mb, _, p, o in problems))
    check(any(o[3].startswith("refused") or o[2] for o in outcomes),
          "no limit made our filter itself run out of memory")


CASES = {
    **{name: (lambda name: lambda s: s.refused(off(name), REFUSED[name]))(name) for name in REFUSED},
    **{name: (lambda name: lambda s: s.flattened(off(name), faces=FLATTENED[name][0],
                                                 warnings=FLATTENED[name][1]))(name)
       for name in FLATTENED},
    "needle_edge": case_needle_edge,
    "source_out_of_range": lambda s: s.refused(
        off("wavy"), "source vertex 100000 is not a vertex of the patch",
        params={"sourcevertex": "100000"}),
    "source_on_boundary": lambda s: s.refused(
        off("wavy"), "source vertex 3 is on the boundary; the measured boundary needs an interior "
                     "vertex", params={"sourcevertex": "3"}),
    # MeshLab 2020.09 holds coordinates in single precision: at 1e6 its loader rounds them to
    # 1/16, so the map is that of the rounded mesh (valid, L2 within 1 %).
    "offset_1e6": lambda s: case_scaled(s, "offset_1e6", 1e-2),
    "scaled_1e-6": lambda s: case_scaled(s, "scaled_1e-6", 1e-4),
    "unreadable_empty": lambda s: s.refused(b"", None, loader=True),
    "unreadable_garbage": lambda s: s.refused(bytes(range(256)) * 4, None, loader=True),
    "selected_none": lambda s: s.refused(off("wavy"), "no faces are selected",
                                         params={"selectedonly": "true"}, before=[SELECT_NONE]),
    "selected_two_regions": lambda s: s.refused(
        off("wavy"), "the mesh has 2 connected components; a patch must be one piece (select one "
                     "component, or use the atlas filter: Straightest Distances Atlas; --atlas in "
                     "the CLI)", params={"selectedonly": "true"},
        before=[select_faces("(x0 < 0.3 && x1 < 0.3 && x2 < 0.3) || "
                             "(x0 > 0.7 && x1 > 0.7 && x2 > 0.7)")]),
    "selected_disk": case_selected_disk,
    "deleted_faces": lambda s: case_deleted(s, DELETE_FACES),
    "deleted_faces_and_vertices": lambda s: case_deleted(s, DELETE_FACES_AND_VERTICES),
    "out_of_memory": None,  # needs --big (see main)
}


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--prefix", required=True)
    parser.add_argument("--mlx", required=True)
    parser.add_argument("--workdir", required=True)
    parser.add_argument("--big", help="a mesh too large for the memory limits (out_of_memory)")
    parser.add_argument("--list", action="store_true")
    parser.add_argument("case", nargs="?")
    args = parser.parse_args()
    if args.list:
        print("\n".join(CASES))
        return 0
    if args.case not in CASES:
        parser.error(f"unknown case {args.case!r}; one of: {', '.join(CASES)}")
    server = Server(os.path.abspath(args.prefix), args.mlx, os.path.abspath(args.workdir))
    if args.case == "out_of_memory" and not (args.big and os.path.isfile(args.big)):
        parser.error("out_of_memory needs --big MESH.off")
    if args.case == "out_of_memory":
        return meshgen.report_case(args.case, lambda: case_out_of_memory(server, args.big))
    return meshgen.report_case(args.case, lambda: CASES[args.case](server))


if __name__ == "__main__":
    sys.exit(main())
