#!/usr/bin/env python3
"""Writes the small input meshes of resources/meshes/inputs/: the everyday file kinds users bring
(polygon meshes, STL, PLY tristrips, faces wound against their neighbours), made here so the
project may ship them. Plain Python, seeded, so a re-run writes the same bytes:

    python3 scripts/make-input-meshes.py [--out resources/meshes/inputs]
                                         [--from MESH.off --name STEM]

With --from, the STL, tristrip and random-winding kinds are written from another (triangle)
OFF mesh instead of the project's torus, e.g. a model of ../shared/meshes/closed for the bench.
"""
import argparse
import math
import os
import random
import struct


def read_off(path):
    with open(path) as f:
        tokens = [t for line in f for t in line.split("#", 1)[0].split()]
    assert tokens[0].endswith("OFF"), path
    nv, nf = int(tokens[1]), int(tokens[2])
    pos = 4
    V = []
    for _ in range(nv):
        V.append(tuple(float(t) for t in tokens[pos:pos + 3]))
        pos += 3
    F = []
    for _ in range(nf):
        n = int(tokens[pos])
        F.append([int(t) for t in tokens[pos + 1:pos + 1 + n]])
        pos += 1 + n
    return V, F


def write_off(path, V, F):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        for v in V:
            f.write(" ".join(f"{c:.9g}" for c in v) + "\n")
        for face in F:
            f.write(f"{len(face)} " + " ".join(str(i) for i in face) + "\n")


def cube_quads():
    """The unit cube, six quads wound outward."""
    V = [(x, y, z) for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0)]
    F = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    return V, F


def cube_triangles_and_quads():
    """The cube with its bottom quad as two triangles: 2 triangles and 5 quads."""
    V, F = cube_quads()
    a, b, c, d = F[0]
    return V, [[a, b, c], [a, c, d]] + F[1:]


def cube_triangles_quads_and_triangle():
    """The cube as a user's file had it: vertices and faces in another order, one quad split, and
    a separate triangle. Its split diagonal runs through texel centres in the packed atlas, which
    the overlap check once counted as covered twice."""
    V = [(0, 1, 1), (1, 1, 1), (1, 1, 0), (1, 0, 1), (0, 0, 1), (1, 0, 0), (0, 1, 0), (0, 0, 0),
         (3, 3, 3), (4, 3, 3), (3, 4, 3)]
    F = [[6, 0, 1, 2], [5, 3, 4, 7], [5, 7, 6], [5, 6, 2], [0, 6, 7, 4], [1, 0, 4, 3],
         [2, 1, 3, 5], [8, 9, 10]]
    return [tuple(float(c) for c in v) for v in V], F


def wavy_quad_disk(n=12):
    """A curved disk of n x n quads (for the patch filter)."""
    V = [(i / n, j / n, 0.15 * math.sin(3 * i / n + 2 * j / n)) for j in range(n + 1)
         for i in range(n + 1)]
    F = [[j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i]
         for j in range(n) for i in range(n)]
    return V, F


def polygon_prism(sides=6, height=1.5):
    """A hexagonal prism: two hexagons (polygons of `sides` corners) and `sides` quads."""
    V = [(math.cos(2 * math.pi * k / sides), math.sin(2 * math.pi * k / sides), z)
         for z in (0.0, height) for k in range(sides)]
    bottom = list(reversed(range(sides)))
    top = [sides + k for k in range(sides)]
    sides_F = [[k, (k + 1) % sides, sides + (k + 1) % sides, sides + k] for k in range(sides)]
    return V, [bottom, top] + sides_F


def torus_quads(n=24, m=12, R=1.0, r=0.4):
    """A torus of n x m quads wound outward."""
    V = []
    for i in range(n):
        a = 2 * math.pi * i / n
        for j in range(m):
            b = 2 * math.pi * j / m
            V.append(((R + r * math.cos(b)) * math.cos(a), (R + r * math.cos(b)) * math.sin(a),
                      r * math.sin(b)))
    F = []
    for i in range(n):
        for j in range(m):
            i1, j1 = (i + 1) % n, (j + 1) % m
            F.append([i * m + j, i1 * m + j, i1 * m + j1, i * m + j1])
    return V, F


def facet_normal(V, t):
    a, b, c = (V[i] for i in t)
    u = [b[k] - a[k] for k in range(3)]
    w = [c[k] - a[k] for k in range(3)]
    n = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
    length = math.sqrt(sum(x * x for x in n)) or 1.0
    return tuple(x / length for x in n)


def write_stl_binary(path, V, F):
    with open(path, "wb") as f:
        f.write(b"binary STL written by make-input-meshes.py".ljust(80, b" "))
        f.write(struct.pack("<I", len(F)))
        for t in F:
            f.write(struct.pack("<3f", *facet_normal(V, t)))
            for i in t:
                f.write(struct.pack("<3f", *V[i]))
            f.write(b"\0\0")


def write_stl_ascii(path, V, F, name):
    # Coordinates as float32 decimals, so ASCII and binary weld to the same vertices.
    def f32(x):
        return struct.unpack("<f", struct.pack("<f", x))[0]

    with open(path, "w") as f:
        f.write(f"solid {name}\n")
        for t in F:
            f.write("  facet normal " + " ".join(f"{c:.7e}" for c in facet_normal(V, t)) + "\n")
            f.write("    outer loop\n")
            for i in t:
                f.write("      vertex " + " ".join(repr(f32(c)) for c in V[i]) + "\n")
            f.write("    endloop\n  endfacet\n")
        f.write(f"endsolid {name}\n")


def tristrips(F, seed=7, max_strip=40):
    """Greedy strips over the triangles, in Stanford's convention: a strip's k-th triangle is
    (s[k], s[k+1], s[k+2]) with the winding swapped on odd k, strips joined by -1 restarts; a
    few strips are instead joined by repeated vertices (degenerate joins), as strippers do."""
    rng = random.Random(seed)
    edge_faces = {}
    for f, t in enumerate(F):
        for k in range(3):
            edge_faces.setdefault((t[k], t[(k + 1) % 3]), []).append(f)
    used = [False] * len(F)
    strips = []
    for start in range(len(F)):
        if used[start]:
            continue
        used[start] = True
        a, b, c = F[start]
        strip = [a, b, c]
        while len(strip) < max_strip:
            # The next triangle shares the strip's last edge, wound as the strip's parity asks.
            p, q = strip[-2], strip[-1]
            odd = len(strip) % 2 == 1  # the triangle about to be formed has index len-2
            edge = (q, p) if odd else (p, q)
            nxt = [f for f in edge_faces.get(edge, []) if not used[f]]
            if not nxt:
                break
            t = F[nxt[0]]
            apex = [v for v in t if v not in (p, q)]
            if len(apex) != 1:
                break
            used[nxt[0]] = True
            strip.append(apex[0])
        strips.append(strip)
    # Join strips: mostly by -1, every fifth by a degenerate bridge (repeat last and first vertex,
    # plus one more when the parity would flip the next strip's winding).
    out = []
    run = 0  # entries since the last -1: a triangle's parity counts from there
    for strip in strips:
        if out and rng.random() < 0.2:
            out += [out[-1], strip[0]]
            run += 2
            if run % 2 == 1:
                out.append(strip[0])
                run += 1
        elif out:
            out.append(-1)
            run = 0
        out += strip
        run += len(strip)
    return out


def write_ply_tristrips(path, V, F):
    strip = tristrips(F)
    with open(path, "wb") as f:
        header = ("ply\nformat binary_little_endian 1.0\n"
                  "comment tristrips written by make-input-meshes.py\n"
                  f"element vertex {len(V)}\nproperty float x\nproperty float y\nproperty float z\n"
                  "element tristrips 1\nproperty list int int vertex_indices\nend_header\n")
        f.write(header.encode())
        for v in V:
            f.write(struct.pack("<3f", *v))
        f.write(struct.pack("<i", len(strip)))
        f.write(struct.pack(f"<{len(strip)}i", *strip))


def randomly_wound(F, seed=2):
    """Each face's winding reversed with probability 1/2 (seeded)."""
    rng = random.Random(seed)
    return [list(reversed(t)) if rng.random() < 0.5 else list(t) for t in F]


def triangles_of(F):
    out = []
    for face in F:
        out += [[face[0], face[k], face[k + 1]] for k in range(1, len(face) - 1)]
    return out


def write_derived(out, stem, V, F):
    """The STL pair, the tristrip PLY and the randomly wound OFF of one triangle mesh."""
    T = triangles_of(F)
    write_stl_binary(os.path.join(out, f"{stem}_binary.stl"), V, T)
    write_stl_ascii(os.path.join(out, f"{stem}_ascii.stl"), V, T, stem)
    write_ply_tristrips(os.path.join(out, f"{stem}_tristrips.ply"), V, T)
    write_off(os.path.join(out, f"{stem}_random_winding.off"), V, randomly_wound(T))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=os.path.join(here, "..", "resources", "meshes", "inputs"))
    parser.add_argument("--from", dest="source", help="triangle OFF mesh for the derived kinds")
    parser.add_argument("--name", help="file stem of the derived kinds (with --from)")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.source:
        V, F = read_off(args.source)
        write_derived(args.out, args.name or os.path.splitext(os.path.basename(args.source))[0],
                      V, F)
        return
    write_off(os.path.join(args.out, "cube_quads.off"), *cube_quads())
    write_off(os.path.join(args.out, "cube_triangles_quads.off"), *cube_triangles_and_quads())
    write_off(os.path.join(args.out, "cube_triangles_quads_triangle.off"),
              *cube_triangles_quads_and_triangle())
    write_off(os.path.join(args.out, "prism_hexagons.off"), *polygon_prism())
    write_off(os.path.join(args.out, "torus_quads.off"), *torus_quads())
    write_off(os.path.join(args.out, "disk_quads.off"), *wavy_quad_disk())
    torus = read_off(os.path.join(here, "..", "resources", "meshes", "closed", "torus.off"))
    write_derived(args.out, "torus", *torus)


if __name__ == "__main__":
    main()
