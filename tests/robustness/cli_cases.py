#!/usr/bin/env python3
"""The robustness cases (tests/robustness/CASES.md) through the straightest_param command line.

usage: cli_cases.py --exe STRAIGHTEST_PARAM --workdir DIR [--meshes DIR] [--big MESH.off] CASE

One ctest per CASE (see CMakeLists.txt). Every run also checks that the input file is left as it
was. The failure contract (cli/main.cpp, docs/method.md section 6): exit status 1, exactly one stderr line
"straightest_param: <reason>", nothing on stdout, no output file written and an existing output
file left untouched. The success contract: exit status 0, the report on stdout with 0 flipped
faces, stderr lines only "warning: ...", and output files (OBJ and PLY) that hold the input mesh
unchanged with per-wedge UVs in which every face has positive area (recomputed here from the
files, never taken from the report).
"""
import argparse
import hashlib
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "meshlab"))
import meshgen  # noqa: E402
from meshgen import check  # noqa: E402
from check_obj_uv import read_obj, sander_stretch  # noqa: E402

PREFIX = "straightest_param: "


class Cli:
    def __init__(self, exe, workdir, meshes):
        self.exe = exe
        self.workdir = workdir
        self.meshes = meshes
        shutil.rmtree(workdir, ignore_errors=True)
        os.makedirs(workdir)
        self.runs = 0

    def mesh(self, name, mesh=None):
        """Writes a generated mesh (meshgen case `name`, or `mesh`) and returns its path."""
        path = os.path.join(self.workdir, name + ".off")
        meshgen.write_off(path, mesh if mesh is not None else meshgen.CASES[name]())
        return path

    def fresh_dir(self):
        self.runs += 1
        folder = os.path.join(self.workdir, f"run{self.runs}")
        os.makedirs(folder)
        return folder

    def run(self, args, memory_kb=None):
        """Runs the tool; returns (exit status, stdout, stderr). Inputs must not change."""
        inputs = [a for a in args if os.path.isfile(a) and a.endswith((".off", ".obj", ".ply"))
                  and not a.startswith(self.workdir + "/run")]
        digests = {a: digest(a) for a in inputs}
        command = [self.exe] + list(args)
        if memory_kb is not None:
            command = ["bash", "-c", f'ulimit -v {memory_kb}; exec "$0" "$@"'] + command
        done = subprocess.run(command, stdin=subprocess.DEVNULL, capture_output=True, timeout=300)
        for a, d in digests.items():
            check(digest(a) == d, f"the input {a} was modified")
        status = done.returncode if done.returncode >= 0 else 128 - done.returncode
        return status, done.stdout.decode(errors="replace"), done.stderr.decode(errors="replace")

    # --- the two contracts -----------------------------------------------------------------------

    def expect_failure(self, input_path, reason, extra=(), exit_code=1, exact=True):
        """Fails twice: OBJ output + report into an empty folder (must stay empty), and PLY
        output over an existing file (must stay as it was). Returns the reason."""
        folder = self.fresh_dir()
        results = [self.run([input_path, os.path.join(folder, "out.obj"), "--report",
                             os.path.join(folder, "report.json")] + list(extra))]
        check(os.listdir(folder) == [], f"files written on failure: {os.listdir(folder)}")
        existing = os.path.join(folder, "existing.ply")
        with open(existing, "w") as f:
            f.write("previous\n")
        results.append(self.run([input_path, existing] + list(extra)))
        with open(existing) as f:
            check(f.read() == "previous\n", "an existing output file was changed on failure")
        check(os.listdir(folder) == ["existing.ply"], f"files written: {os.listdir(folder)}")
        reasons = []
        for status, out, err in results:
            check(status == exit_code, f"exit status {status}, expected {exit_code}; stderr: {err!r}")
            lines = err.splitlines()
            check(len(lines) == 1, f"stderr must be exactly one line, got {err!r}")
            check(lines[0].startswith(PREFIX), f"stderr line lacks '{PREFIX}': {lines[0]!r}")
            check(out == "", f"stdout not empty on failure: {out!r}")
            got = lines[0][len(PREFIX):]
            if exact:
                check(got == reason, f"reason {got!r}, expected {reason!r}")
            else:
                check(reason in got, f"reason {got!r} does not mention {reason!r}")
            reasons.append(got)
        print(f"PASS failure: {reasons[0]}")
        return reasons[0]

    def expect_success(self, input_path, extra=(), warnings=(), formats=("obj", "ply"),
                       input_mesh=None, triangulated=False):
        """Runs into an empty folder per format; checks the report and the written files.
        Returns {format: (report, uv per vertex from the file)}."""
        V, F = input_mesh if input_mesh is not None else read_off(input_path)
        results = {}
        for fmt in formats:
            folder = self.fresh_dir()
            out_path = os.path.join(folder, "out." + fmt)
            status, out, err = self.run([input_path, out_path] + list(extra))
            check(status == 0, f"exit status {status}; stderr: {err!r}")
            lines = err.splitlines()
            for line in lines:
                check(line.startswith("warning: "), f"stderr line is not a warning: {line!r}")
            for expected in warnings:
                check(f"warning: {expected}" in lines, f"missing warning {expected!r} in {lines}")
            report = json.loads(out)
            check(report["flipped_faces"] == 0, f"report says {report['flipped_faces']} flipped")
            expected_files = (["out.mtl", "out.obj", "out_checker.png"] if fmt == "obj"
                              else ["out.ply"])
            check(sorted(os.listdir(folder)) == expected_files,
                  f"output files {sorted(os.listdir(folder))}, expected {expected_files}")
            if fmt == "obj":
                positions, faces, uv = load_obj(out_path)
            else:
                positions, faces, uv = load_ply(out_path)
            check_positions(V, positions, fmt)
            if not triangulated:
                check([list(f) for f in faces] == [list(f) for f in F],
                      f"{fmt}: the faces written differ from the input")
            check(len(faces) == report["faces"], f"{fmt}: {len(faces)} faces, report "
                  f"{report['faces']}")
            bad = non_positive_faces(uv)
            check(bad == 0, f"{fmt}: {bad} of {len(uv)} faces have non-positive UV area in the "
                  "file, while the report says 0 flipped")
            if fmt == "obj" and report["l2_stretch"] is not None:
                l2, _ = sander_stretch([([positions[v] for v in f], uvf)
                                        for f, uvf in zip(faces, uv)])
                check(math.isclose(l2, report["l2_stretch"], rel_tol=1e-6),
                      f"L2 of the file {l2} != reported {report['l2_stretch']}")
            results[fmt] = (report, uv)
        print(f"PASS success: {json.dumps({k: results[formats[0]][0][k] for k in ('l2_stretch', 'boundary_used', 'holes_filled', 'warnings')})}")
        return results


def digest(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def read_off(path):
    words = []
    with open(path) as f:
        for line in f:
            words += line.split("#")[0].split()
    nv, nf = int(words[1]), int(words[2])
    V = [tuple(float(w) for w in words[4 + 3 * i:7 + 3 * i]) for i in range(nv)]
    at, F = 4 + 3 * nv, []
    for _ in range(nf):
        n = int(words[at])
        F.append([int(w) for w in words[at + 1:at + 1 + n]])
        at += 1 + n
    return V, F


def load_obj(path):
    positions, uvs, faces, _ = read_obj(path)
    out_faces, out_uv = [], []
    for corners in faces:
        check(len(corners) == 3 and all(vt is not None for _, vt in corners),
              "an OBJ face without per-wedge texture coordinates")
        out_faces.append([v - 1 for v, _ in corners])
        out_uv.append([uvs[vt - 1] for _, vt in corners])
    return positions, out_faces, out_uv


def load_ply(path):
    """The binary little-endian PLY our writer makes: float x y z; uchar-int vertex_indices;
    uchar-float texcoord (6 per face)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    check("format binary_little_endian 1.0" in header, "PLY is not binary little endian")
    elements, current = [], None
    for line in header:
        parts = line.split()
        if parts[0] == "element":
            current = (parts[1], int(parts[2]), [])
            elements.append(current)
        elif parts[0] == "property":
            current[2].append(parts[1:])
    codes = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I",
             "float": "f", "double": "d", "int8": "b", "uint8": "B", "int32": "i",
             "uint32": "I", "float32": "f", "float64": "d"}
    at = end
    values = {}
    for name, count, props in elements:
        rows = []
        for _ in range(count):
            row = []
            for prop in props:
                if prop[0] == "list":
                    (n,) = struct.unpack_from("<" + codes[prop[1]], data, at)
                    at += struct.calcsize(codes[prop[1]])
                    fmt = "<" + codes[prop[2]] * n
                    row.append(list(struct.unpack_from(fmt, data, at)))
                    at += struct.calcsize(fmt)
                else:
                    (x,) = struct.unpack_from("<" + codes[prop[0]], data, at)
                    at += struct.calcsize(codes[prop[0]])
                    row.append(x)
            rows.append(row)
        values[name] = rows
    positions = [tuple(r[:3]) for r in values["vertex"]]
    faces = [r[0] for r in values["face"]]
    uv = [[(r[1][2 * k], r[1][2 * k + 1]) for k in range(3)] for r in values["face"]]
    return positions, faces, uv


def non_positive_faces(uv):
    bad = 0
    for (s1, t1), (s2, t2), (s3, t3) in uv:
        if (s2 - s1) * (t3 - t1) - (s3 - s1) * (t2 - t1) <= 0:
            bad += 1
    return bad


def check_positions(V, positions, fmt):
    """The written mesh is the input mesh: each coordinate within 1e-6 of the mesh's size
    (single precision would pass for meshes near the origin, not for a scan far from it)."""
    check(len(positions) == len(V), f"{fmt}: {len(positions)} vertices written, input {len(V)}")
    finite = [p for p in V if all(math.isfinite(c) for c in p)]
    size = max(max(p[k] for p in finite) - min(p[k] for p in finite) for k in range(3)) or 1.0
    worst, where = 0.0, -1
    for i, (p, q) in enumerate(zip(V, positions)):
        for a, b in zip(p, q):
            if math.isnan(a) and math.isnan(b):
                continue
            if math.isinf(a) or math.isinf(b):
                check(a == b, f"{fmt}: vertex {i} written as {q}, input {p}")
                continue
            if abs(a - b) > worst:
                worst, where = abs(a - b), i
    check(worst <= 1e-6 * size, f"{fmt}: vertex {where} moved by {worst:g} (mesh size {size:g}): "
          f"written {positions[where]}, input {V[where]}")


def uv_per_vertex(faces, uv, count):
    out = [None] * count
    for f, corners in zip(faces, uv):
        for v, t in zip(f, corners):
            out[v] = t
    return out


def similarity_residual(base, other):
    """Largest |other - (s * base + t)| over the spread of base, for the best s and t."""
    n = len(base)
    mb = [sum(p[k] for p in base) / n for k in range(2)]
    mo = [sum(p[k] for p in other) / n for k in range(2)]
    b = [(p[0] - mb[0], p[1] - mb[1]) for p in base]
    o = [(p[0] - mo[0], p[1] - mo[1]) for p in other]
    bb = sum(x * x + y * y for x, y in b)
    s = sum(x1 * x2 + y1 * y2 for (x1, y1), (x2, y2) in zip(b, o)) / bb
    spread = math.sqrt(bb / n)
    worst = max(max(abs(x2 - s * x1), abs(y2 - s * y1)) for (x1, y1), (x2, y2) in zip(b, o))
    return worst / (abs(s) * spread)


# --- the cases -------------------------------------------------------------------------------------

REFUSED = meshgen.REFUSED_REASONS


def case_refused(cli, name):
    cli.expect_failure(cli.mesh(name), REFUSED[name])


def case_holes(cli, name, holes):
    results = cli.expect_success(cli.mesh(name))
    for report, _ in results.values():
        check(report["holes_filled"] == holes, f"holes_filled {report['holes_filled']}")


def case_quads(cli):
    path = cli.mesh("quads")
    V, _ = meshgen.quads()
    results = cli.expect_success(path, input_mesh=(V, None), triangulated=True,
                                 warnings=["16 polygons with more than 3 vertices were "
                                           "fan-triangulated"])
    folder = cli.fresh_dir()
    _, _, err = cli.run([path, os.path.join(folder, "out.ply"), "--quiet"])
    check(err.splitlines()[0].startswith("warning: 16 polygons"),
          f"the triangulation warning is not first: {err!r}")
    for report, _ in results.values():
        check(report["faces"] == 32, f"faces {report['faces']}, expected 32 triangles")


def case_degenerate(cli, name, warnings=()):
    cli.expect_success(cli.mesh(name), warnings=warnings)
    for boundary in ("circle", "square"):
        for weights in ("straightest", "ltd", "floater", "mean_value", "uniform"):
            cli.expect_success(cli.mesh(name), extra=["--boundary", boundary, "--weights", weights],
                               formats=("obj",))


def case_needle_edge(cli, eps):
    """An interior vertex 1e-7 (or 1e-10) of an edge length from its neighbour."""
    n = 8
    V, F = meshgen.wavy(n)
    v, w = meshgen.grid_index(n, 4, 4), meshgen.grid_index(n, 5, 4)
    V[v] = tuple(p + (q - p) * (1 - eps) for p, q in zip(V[v], V[w]))
    path = cli.mesh("needle_edge", (V, F))
    # One-to-one in double (OBJ keeps 17 digits). PLY's float texture coordinates would
    # collapse the two needle faces: the core repairs the map as stored, and the file (read back
    # by expect_success) has no face of non-positive area.
    results = cli.expect_success(path)
    obj, ply = results["obj"][0], results["ply"][0]
    check(obj["storage"] == {"precision": "double", "degenerate_faces": 0, "moved_vertices": 0},
          f"OBJ storage {obj['storage']}")
    check(ply["storage"]["precision"] == "float", f"PLY storage {ply['storage']}")
    check(ply["storage"]["degenerate_faces"] == 2 and ply["storage"]["moved_vertices"] > 0,
          f"PLY: expected the two needle faces repaired, got {ply['storage']}")


def case_duplicate_vertex_unused(cli):
    results = cli.expect_success(cli.mesh("duplicate_vertex_unused"))
    for report, _ in results.values():
        check(report["vertices"] == 49 and report["unreferenced_vertices"] == 49,
              f"vertices {report['vertices']}, unreferenced {report['unreferenced_vertices']}")


def case_duplicate_vertex_seam(cli):
    path = cli.mesh("duplicate_vertex_seam")
    V, F = read_off(path)
    results = cli.expect_success(path)
    _, uv = results["obj"]
    per_vertex = uv_per_vertex(F, uv, len(V))
    # Seam copies (appended after the 81 grid vertices) sit where their originals are in 3D but
    # on the other side of the slit in UV, except at the slit's mouth on the outer boundary.
    for copy in range(81, len(V)):
        original = V.index(V[copy])
        d = math.dist(per_vertex[copy], per_vertex[original])
        check(d > 1e-6, f"seam vertex {copy} and its twin {original} share a UV point")


def case_unreferenced_vertices(cli):
    results = cli.expect_success(cli.mesh("unreferenced_vertices"))
    for report, _ in results.values():
        check(report["unreferenced_vertices"] == 3, f"unreferenced {report['unreferenced_vertices']}")


def case_no_interior(cli, name):
    path = cli.mesh(name)
    cli.expect_success(path, warnings=["the patch has no interior vertex to measure the boundary "
                                       "from; used the circle boundary instead"])
    for boundary in ("circle", "square"):
        for weights in ("straightest", "ltd", "floater", "mean_value", "uniform"):
            cli.expect_success(path, extra=["--boundary", boundary, "--weights", weights],
                               formats=("obj",))
    cli.expect_failure(path, "source vertex 1 is on the boundary; the measured boundary needs an "
                             "interior vertex", extra=["--source", "1"])


def case_source(cli):
    V, F = meshgen.wavy(6)
    path = cli.mesh("source", (V + [(9.0, 9.0, 9.0)], F))  # vertex 49: used by no face
    cli.expect_failure(path, "source vertex 50 is out of range (the mesh has 50 vertices)",
                       extra=["--source", "50"])
    cli.expect_failure(path, "source vertex 49 is not used by any face", extra=["--source", "49"])
    cli.expect_failure(path, "source vertex 3 is on the boundary; the measured boundary needs an "
                             "interior vertex", extra=["--source", "3"])
    cli.expect_failure(path, "--source must be between -1 and 2147483647, got -2",
                       extra=["--source", "-2"], exit_code=2)
    ok = cli.expect_success(path, extra=["--source", "17"])
    check(ok["obj"][0]["source_vertex"] == 17, "the given source was not used")
    # Circle and square do not use S: a boundary vertex is accepted and not reported.
    ok = cli.expect_success(path, extra=["--source", "3", "--boundary", "circle"])
    check(ok["obj"][0]["source_vertex"] == -1, "circle reports a source vertex")


def case_scale_translation(cli):
    """Offset by 1e6 and scaled by 1e-6: the same report and the same map up to scale (OBJ)."""
    base = cli.expect_success(cli.mesh("wavy"), formats=("obj",))["obj"]
    for name in ("offset_1e6", "scaled_1e-6"):
        for boundary in ("measured", "circle", "square"):
            extra = ["--boundary", boundary]
            ref = base if boundary == "measured" else cli.expect_success(
                cli.mesh("wavy"), extra=extra, formats=("obj",))["obj"]
            got = cli.expect_success(cli.mesh(name), extra=extra, formats=("obj",))["obj"]
            for key in ("l2_stretch", "linf_stretch"):
                check(math.isclose(got[0][key], ref[0][key], rel_tol=1e-6),
                      f"{name} {boundary}: {key} {got[0][key]} != {ref[0][key]}")
            check(got[0]["source_vertex"] == ref[0]["source_vertex"], f"{name}: source differs")
            r = similarity_residual([p for f in ref[1] for p in f], [p for f in got[1] for p in f])
            check(r < 1e-6, f"{name} {boundary}: the map differs from the base map by {r:g}")


def case_offset_ply(cli):
    """The PLY written for a scan offset by 1e6 must still hold the input mesh."""
    cli.expect_success(cli.mesh("offset_1e6"), formats=("ply",))


def write_bytes(cli, name, data):
    path = os.path.join(cli.workdir, name)
    with open(path, "wb") as f:
        f.write(data)
    return path


def case_unreadable(cli):
    """Files that cannot be read as a mesh: exit 1, one line naming the file."""
    good = meshgen.off_text(meshgen.wavy(4))
    cut_in_faces = good[:good.rindex("3 ", 0, len(good) - 40)]
    cases = {
        "bundled truncated.off": os.path.join(cli.meshes, "invalid", "truncated.off"),
        "empty": write_bytes(cli, "empty.off", b""),
        "cut in the faces": write_bytes(cli, "cut.off", cut_in_faces.encode()),
        "binary garbage": write_bytes(cli, "garbage.off", bytes(range(256)) * 4),
        "garbage ply": write_bytes(cli, "garbage.ply", b"ply\nformat binary_little_endian 1.0\n"
                                   b"element vertex 100000000000\nend_header\n\x00\x01"),
        "obj without faces": write_bytes(cli, "nofaces.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
        "absurd counts": write_bytes(cli, "absurd.off", b"OFF\n2000000000 2000000000 0\n0 0 0\n"),
        "a folder": os.path.join(cli.workdir, "folder.off"),
        "missing": os.path.join(cli.workdir, "missing.off"),
    }
    os.makedirs(cases["a folder"], exist_ok=True)
    for what, path in cases.items():
        reason = cli.expect_failure(path, os.path.basename(path), exact=False)
        print(f"  {what}: {reason}")


def peak_virtual_kb(command, **kwargs):
    """Runs `command` without limits and returns its peak virtual memory (VmPeak, kB), sampled
    from /proc until it exits: the address space it needs on this machine (thread stacks and
    malloc arenas depend on the number of cores)."""
    process = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL, **kwargs)
    peak = 0
    while process.poll() is None:
        try:
            with open(f"/proc/{process.pid}/status") as f:
                for line in f:
                    if line.startswith("VmPeak:"):
                        peak = max(peak, int(line.split()[1]))
        except OSError:
            pass
        time.sleep(0.02)
    check(process.returncode == 0, f"the unlimited run failed ({process.returncode})")
    check(peak > 0, "could not measure the peak virtual memory")
    return peak


def case_out_of_memory(cli, big):
    """A mesh too large for the memory it may use: `ulimit -v` from 15 % to 110 % of what the
    run needs without a limit. Every run either succeeds or fails with one stderr line naming
    memory, exit status 1 and nothing written; never an abort or another program's message."""
    folder = cli.fresh_dir()
    peak = peak_virtual_kb([cli.exe, big, os.path.join(folder, "free.ply"), "--quiet"])
    print(f"  unlimited run: VmPeak {peak >> 10} MB")
    outcomes = []
    for step in range(20):
        limit_kb = int(peak * (0.15 + step * 0.05))
        folder = cli.fresh_dir()
        out_path = os.path.join(folder, "big.ply")
        status, out, err = cli.run([big, out_path, "--quiet"], memory_kb=limit_kb)
        lines = err.splitlines()
        problem = None
        if status == 0:
            outcome = "success"
            if os.listdir(folder) != ["big.ply"]:
                problem = f"outputs {os.listdir(folder)}"
        else:
            outcome = lines[0] if lines else ""
            if status != 1:
                problem = f"exit status {status}"
            elif len(lines) != 1 or not lines[0].startswith(PREFIX) or "memory" not in lines[0]:
                problem = "stderr is not one line about memory"
            elif os.listdir(folder):
                problem = f"files written: {os.listdir(folder)}"
        detail = err.strip().replace("\n", " | ")
        outcomes.append((limit_kb >> 10, problem, outcome if not problem else detail))
    for limit_mb, problem, text in outcomes:
        print(f"  {limit_mb} MB: {'PROBLEM: ' + problem + ': ' if problem else ''}{text}")
    problems = [o for o in outcomes if o[1]]
    check(not problems, f"{len(problems)} memory limits broke the contract: " +
          "; ".join(f"{mb} MB: {p} ({t})" for mb, p, t in problems))
    check(any(o[2] != "success" for o in outcomes), "no limit was small enough to fail")
    check(any("not enough memory to parameterize" in o[2] for o in outcomes),
          "no limit let the core itself run out of memory")


CASES = {
    **{name: (lambda name: lambda cli, args: case_refused(cli, name))(name) for name in REFUSED},
    "annulus": lambda cli, args: case_holes(cli, "annulus", 1),
    "two_holes": lambda cli, args: case_holes(cli, "two_holes", 2),
    "quads": lambda cli, args: case_quads(cli),
    "zero_area": lambda cli, args: case_degenerate(
        cli, "zero_area", ["4 vertices with a degenerate 1-ring used uniform weights"]),
    "needles": lambda cli, args: case_degenerate(cli, "needles"),
    "needle_edge_1e-7": lambda cli, args: case_needle_edge(cli, 1e-7),
    "needle_edge_1e-10": lambda cli, args: case_needle_edge(cli, 1e-10),
    "duplicate_vertex_unused": lambda cli, args: case_duplicate_vertex_unused(cli),
    "duplicate_vertex_seam": lambda cli, args: case_duplicate_vertex_seam(cli),
    "unreferenced_vertices": lambda cli, args: case_unreferenced_vertices(cli),
    "one_triangle": lambda cli, args: case_no_interior(cli, "one_triangle"),
    "no_interior_vertex": lambda cli, args: case_no_interior(cli, "no_interior_vertex"),
    "source_vertex": lambda cli, args: case_source(cli),
    "scale_translation": lambda cli, args: case_scale_translation(cli),
    "offset_1e6_ply": lambda cli, args: case_offset_ply(cli),
    "unreadable_files": lambda cli, args: case_unreadable(cli),
    "out_of_memory": lambda cli, args: case_out_of_memory(cli, args.big),
}


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--exe", required=True)
    parser.add_argument("--workdir", required=True)
    parser.add_argument("--meshes", default=os.path.join(HERE, "..", "..", "resources", "meshes"),
                        help="the meshes that ship with the repository")
    parser.add_argument("--big", help="a mesh too large for the memory limits (out_of_memory)")
    parser.add_argument("--list", action="store_true", help="print the case names")
    parser.add_argument("case", nargs="?")
    args = parser.parse_args()
    if args.list:
        print("\n".join(CASES))
        return 0
    if args.case not in CASES:
        parser.error(f"unknown case {args.case!r}; one of: {', '.join(CASES)}")
    if args.case == "out_of_memory" and not (args.big and os.path.isfile(args.big)):
        parser.error("out_of_memory needs --big MESH.off")
    cli = Cli(os.path.abspath(args.exe), os.path.abspath(args.workdir), args.meshes)
    return meshgen.report_case(args.case, lambda: CASES[args.case](cli, args))


if __name__ == "__main__":
    sys.exit(main())
