#!/usr/bin/env python3
"""Checks an OBJ written by meshlabserver -m wt after the straightest-distances filter.

Recomputes from the file alone: every face has per-wedge texture coordinates, no face is flipped
or degenerate in UV (signed area > 0; faces wound against their neighbours, as many as the log
says, are measured turned over, as the atlas charts them), the .mtl's map_Kd texture exists, and -- given the
meshlabserver log -- the Sander L2 stretch (docs/method.md section 5) matches the logged one. Plain
Python: it runs with any python3.
"""
import argparse
import math
import os
import re
import sys


def read_obj(path):
    positions, uvs, faces, mtllibs = [], [], [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                positions.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == "vt":
                uvs.append(tuple(float(x) for x in parts[1:3]))
            elif parts[0] == "f":
                corners = []
                for corner in parts[1:]:
                    fields = corner.split("/")
                    vt = int(fields[1]) if len(fields) > 1 and fields[1] else None
                    corners.append((int(fields[0]), vt))
                faces.append(corners)
            elif parts[0] == "mtllib":
                mtllibs.append(line.strip()[len("mtllib"):].strip())
    return positions, uvs, faces, mtllibs


def index(i, count):  # OBJ indices are 1-based; negative ones count from the end
    return i - 1 if i > 0 else count + i


def sander_stretch(triangles):
    """triangles: [(q0,q1,q2), (p0,p1,p2)] -> (L2, Linf) normalized so 1.0 is optimal."""
    sum_l2_area3 = sum_area3 = sum_area2 = 0.0
    linf = 0.0
    for q, p in triangles:
        (s1, t1), (s2, t2), (s3, t3) = p
        area2 = ((s2 - s1) * (t3 - t1) - (s3 - s1) * (t2 - t1)) / 2.0
        e1 = [q[1][i] - q[0][i] for i in range(3)]
        e2 = [q[2][i] - q[0][i] for i in range(3)]
        cross = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                 e1[0] * e2[1] - e1[1] * e2[0]]
        area3 = math.sqrt(sum(c * c for c in cross)) / 2.0
        ss = [(q[0][i] * (t2 - t3) + q[1][i] * (t3 - t1) + q[2][i] * (t1 - t2)) / (2 * area2)
              for i in range(3)]
        st = [(q[0][i] * (s3 - s2) + q[1][i] * (s1 - s3) + q[2][i] * (s2 - s1)) / (2 * area2)
              for i in range(3)]
        a = sum(x * x for x in ss)
        b = sum(x * y for x, y in zip(ss, st))
        c = sum(x * x for x in st)
        sum_l2_area3 += (a + c) / 2.0 * area3
        sum_area3 += area3
        sum_area2 += area2
        linf = max(linf, math.sqrt(((a + c) + math.sqrt((a - c) ** 2 + 4 * b * b)) / 2.0))
    scale = math.sqrt(sum_area2 / sum_area3)
    return math.sqrt(sum_l2_area3 / sum_area3) * scale, linf * scale


def count_charts(faces, uvs):
    """Faces joined across an edge whose two sides carry the same UV values."""
    parent = list(range(len(faces)))

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x
    sides = {}
    for f, corners in enumerate(faces):
        for k in range(len(corners)):
            (a, ta), (b, tb) = corners[k], corners[(k + 1) % len(corners)]
            key = (min(a, b), max(a, b))
            uv = {a: uvs[index(ta, len(uvs))], b: uvs[index(tb, len(uvs))]}
            for g, other in sides.get(key, []):
                if other == uv:
                    parent[find(f)] = find(g)
            sides.setdefault(key, []).append((f, uv))
    return len({find(f) for f in range(len(faces))})


def coherent_turns(faces):
    """Per face, whether to turn it over so faces joined across two-face edges agree, keeping in
    each piece the winding most of its faces have (as the atlas does, core/common/connectivity.h)."""
    edges = {}
    for f, corners in enumerate(faces):
        n = len(corners)
        for k in range(n):
            a, b = corners[k][0], corners[(k + 1) % n][0]
            edges.setdefault((min(a, b), max(a, b)), []).append((f, a))
    neighbours = [[] for _ in faces]
    for pairs in edges.values():
        if len(pairs) == 2:
            (f, a), (g, b) = pairs
            neighbours[f].append((g, a != b))  # agree: the edge runs the other way in g
            neighbours[g].append((f, a != b))
    turn, seen = [False] * len(faces), [False] * len(faces)
    for start in range(len(faces)):
        if seen[start]:
            continue
        piece, seen[start] = [start], True
        for f in piece:
            for g, agree in neighbours[f]:
                if not seen[g]:
                    seen[g], turn[g] = True, turn[f] != (not agree)
                    piece.append(g)
        if 2 * sum(turn[f] for f in piece) > len(piece):
            for f in piece:
                turn[f] = not turn[f]
    return turn


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("obj")
    parser.add_argument("--log", help="meshlabserver output holding the filter's report line")
    parser.add_argument("--l2-tolerance", type=float, default=2e-3,
                        help="relative; the OBJ keeps only 6 decimals per coordinate")
    parser.add_argument("--max-l2", type=float, help="fail when the file's L2 stretch is above this")
    parser.add_argument("--atlas", action="store_true",
                        help="the atlas filter's output: every UV in [0,1], and the charts (faces "
                             "joined across edges with the same UVs on both sides) as logged")
    args = parser.parse_args()

    problems = []
    positions, uvs, faces, mtllibs = read_obj(args.obj)
    if not faces:
        problems.append("no faces")
    # Faces wound against their neighbours, which the atlas charts turned over (their UV
    # triangles then run clockwise): measured turned, and their number as the log gives it.
    logged = None
    if args.log and os.path.exists(args.log):
        with open(args.log, errors="replace") as f:
            found = re.search(r"(\d+) faces are wound against their neighbours", f.read())
        logged = int(found.group(1)) if found else 0
    if logged:
        turns = coherent_turns(faces)
        if sum(turns) != logged:
            problems.append(f"{sum(turns)} faces wound against their neighbours, {logged} logged")
        faces = [[c[0], c[2], c[1]] if t and len(c) == 3 else c for c, t in zip(faces, turns)]
    triangles, flipped, missing_uv = [], 0, 0
    for corners in faces:
        if len(corners) != 3 or any(vt is None for _, vt in corners):
            missing_uv += 1
            continue
        q = [positions[index(v, len(positions))] for v, _ in corners]
        p = [uvs[index(vt, len(uvs))] for _, vt in corners]
        (s1, t1), (s2, t2), (s3, t3) = p
        if (s2 - s1) * (t3 - t1) - (s3 - s1) * (t2 - t1) <= 0:
            flipped += 1
        else:
            triangles.append((q, p))
    if missing_uv:
        problems.append(f"{missing_uv} faces without per-wedge texture coordinates")
    if flipped:
        problems.append(f"{flipped} flipped or degenerate faces in UV")

    folder = os.path.dirname(os.path.abspath(args.obj))
    textures = []
    for mtllib in mtllibs:
        mtl_path = os.path.join(folder, mtllib)
        if not os.path.exists(mtl_path):
            problems.append(f"material file {mtl_path} missing")
            continue
        with open(mtl_path) as f:
            textures += [line.split(None, 1)[1].strip() for line in f
                         if line.startswith("map_Kd") and len(line.split(None, 1)) == 2]
    if not textures:
        problems.append("no map_Kd texture in the material file")
    for texture in textures:
        if not os.path.exists(os.path.join(folder, texture)):  # join keeps absolute paths
            problems.append(f"texture {texture} missing")

    l2, linf = sander_stretch(triangles) if triangles and not flipped else (float("nan"),) * 2
    print(f"{args.obj}: {len(faces)} faces, {flipped} flipped, L2 {l2:.4f}, Linf {linf:.4f}, "
          f"textures {textures}")
    if args.max_l2 is not None and not l2 <= args.max_l2:
        problems.append(f"L2 stretch {l2:.4f} above {args.max_l2}")
    if args.atlas:
        outside = sum(1 for u, v in uvs if not (0 <= u <= 1 and 0 <= v <= 1))
        if outside:
            problems.append(f"{outside} texture coordinates outside [0,1]")
        charts = count_charts(faces, uvs)
        print(f"{args.obj}: {charts} charts by their texture coordinates")
        if args.log:
            with open(args.log, errors="replace") as f:
                logged = re.findall(r"(?<![_a-z])charts ([0-9]+),", f.read())
            if not logged or int(logged[-1]) != charts:
                problems.append(f"logged charts {logged[-1:]} differ from the file's {charts}")
    if args.log:
        with open(args.log, errors="replace") as f:
            logged = re.findall(r"(?:L2 stretch|l2_stretch) ([0-9.eE+-]+)", f.read())
        if not logged:
            problems.append("no 'L2 stretch' line in the log")
        elif not math.isclose(float(logged[-1]), l2, rel_tol=args.l2_tolerance):
            problems.append(f"logged L2 {logged[-1]} differs from the file's {l2:.6f}")

    for problem in problems:
        print("FAIL:", problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
