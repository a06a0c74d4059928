"""Small meshes for the robustness cases (tests/robustness/CASES.md), made in code so every test
knows its input exactly. Plain Python (no numpy): the CLI and meshlabserver drivers run with any
python3, and tests/python/test_robustness.py uses the same cases in pymeshlab.

A mesh is (V, F): V a list of (x, y, z) floats, F a list of vertex index lists (counter-clockwise
seen from +z for the flat ones). `CASES` maps a case name to a function returning the mesh.
"""
import math
import os


class Failure(Exception):
    """A robustness case that did not behave (the message says how)."""


def check(condition, message):
    if not condition:
        raise Failure(message)


def report_case(name, run):
    """Runs one case (a callable), prints PASS or FAIL with the reason, returns the exit status."""
    try:
        run()
    except Failure as failure:
        print(f"FAIL: {name}: {failure}")
        return 1
    print(f"PASS: {name}")
    return 0


def grid(n, sx=1.0, sy=1.0, height=lambda x, y: 0.0, m=None):
    """An (n+1) x (m+1) grid over [0, sx] x [0, sy] with alternating diagonals (a disk)."""
    m = n if m is None else m
    V = [(sx * i / n, sy * j / m, height(sx * i / n, sy * j / m))
         for j in range(m + 1) for i in range(n + 1)]
    F = []
    for j in range(m):
        for i in range(n):
            a = j * (n + 1) + i
            b, c = a + 1, a + n + 1
            d = c + 1
            if (i + j) % 2 == 0:
                F += [[a, b, d], [a, d, c]]
            else:
                F += [[a, b, c], [b, d, c]]
    return V, F


def grid_index(n, i, j):
    return j * (n + 1) + i


def wavy(n=8):
    """A curved disk (not planar, so every weight scheme and the measured boundary have work)."""
    return grid(n, height=lambda x, y: 0.3 * math.sin(3 * x + 2 * y))


def faces_around(F, v):
    return [k for k, f in enumerate(F) if v in f]


# --- the cases -----------------------------------------------------------------------------------

def closed_octahedron():
    V = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    F = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    return V, F


def annulus(segments=12):
    """Two boundary loops: a ring of 2 x segments triangles around a hole (supported: the hole is
    filled virtually)."""
    V, F = [], []
    for k in range(segments):
        a = 2 * math.pi * k / segments
        V.append((math.cos(a), math.sin(a), 0.0))
    for k in range(segments):
        a = 2 * math.pi * k / segments
        V.append((2 * math.cos(a), 2 * math.sin(a), 0.2 * math.sin(2 * a)))
    for k in range(segments):
        i0, i1 = k, (k + 1) % segments
        o0, o1 = segments + k, segments + (k + 1) % segments
        F += [[i0, o0, o1], [i0, o1, i1]]
    return V, F


def two_holes():
    """A wavy grid with two interior faces-pairs removed: three boundary loops."""
    n = 8
    V, F = wavy(n)
    drop = set()
    for (i, j) in [(2, 2), (5, 5)]:
        cell = 2 * (j * n + i)
        drop |= {cell, cell + 1}
    return V, [f for k, f in enumerate(F) if k not in drop]


def two_components():
    V1, F1 = grid(3)
    V2, F2 = grid(3)
    off = len(V1)
    return V1 + [(x + 5, y, z) for x, y, z in V2], F1 + [[a + off for a in f] for f in F2]


def nonmanifold_edge():
    """A fin: a third face on an interior edge of a grid."""
    n = 4
    V, F = grid(n)
    a, b = grid_index(n, 1, 1), grid_index(n, 2, 2)  # the diagonal of cell (1, 1)
    V.append((0.4, 0.6, 1.0))
    F.append([a, b, len(V) - 1])
    return V, F


def nonmanifold_vertex():
    """A pinched vertex: two opposite faces of an interior vertex's ring removed, so its faces form
    two fans while the mesh stays one piece through edges."""
    n = 4
    V, F = grid(n)
    v = grid_index(n, 2, 2)
    ring = faces_around(F, v)
    # Order the ring around v and drop two faces that are not neighbours.
    cx, cy = V[v][0], V[v][1]

    def angle(k):
        f = F[k]
        x = sum(V[u][0] for u in f) / 3 - cx
        y = sum(V[u][1] for u in f) / 3 - cy
        return math.atan2(y, x)

    ring.sort(key=angle)
    drop = {ring[0], ring[len(ring) // 2]}
    return V, [f for k, f in enumerate(F) if k not in drop]


def bowtie():
    """Two triangles sharing only a vertex (two components through edges)."""
    V = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (-1, 0, 0), (-1, -1, 0)]
    return V, [[0, 1, 2], [0, 3, 4]]


def duplicate_face():
    n = 4
    V, F = grid(n)
    return V, F + [list(F[9])]


def duplicate_face_rotated():
    n = 4
    V, F = grid(n)
    f = F[9]
    return V, F + [[f[1], f[2], f[0]]]


def duplicate_face_reversed():
    n = 4
    V, F = grid(n)
    f = F[9]
    return V, F + [[f[0], f[2], f[1]]]


def inconsistent_orientation():
    n = 4
    V, F = grid(n)
    f = F[9]
    F = list(F)
    F[9] = [f[0], f[2], f[1]]
    return V, F


def quads():
    """A 4 x 4 grid of quads on a curved surface (16 quads, 9 interior vertices)."""
    n = 4
    V = [(i / n, j / n, 0.2 * math.sin(3 * i / n) * math.cos(2 * j / n))
         for j in range(n + 1) for i in range(n + 1)]
    F = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            F.append([a, a + 1, a + n + 2, a + n + 1])
    return V, F


def zero_area():
    """An interior vertex moved onto the far edge of one of its faces: that face has zero area."""
    n = 8
    V, F = grid(n, sx=2.0)
    v = grid_index(n, 4, 4)  # (i + j) even: its cell has face (v, v + 1, v + n + 2)
    a, b = V[v + 1], V[v + n + 2]
    V[v] = tuple(0.5 * (p + q) for p, q in zip(a, b))
    return V, F


def needles():
    """A curved 12 x 12 grid whose column 6 is moved to 1e-5 from column 5: a column of needle
    triangles (aspect ratio ~8000) among ordinary ones."""
    n = 12
    V, F = grid(n, height=lambda x, y: 0.1 * x * y)
    V = [(x if abs(x - 6 / n) > 1e-12 else 5 / n + 1e-5, y, z) for x, y, z in V]
    return V, F


def needle_fan():
    """An interior vertex with one neighbour at distance 1e-7 (a very short edge) in a curved
    grid."""
    n = 8
    V, F = wavy(n)
    v, w = grid_index(n, 4, 4), grid_index(n, 5, 4)
    V[v] = tuple(p + (q - p) * (1 - 1e-7) for p, q in zip(V[v], V[w]))
    return V, F


def duplicate_vertex_unused():
    """A copy of every vertex appended, none of the copies used by a face."""
    V, F = wavy(6)
    return V + list(V), F


def duplicate_vertex_seam():
    """A cut from the boundary into the middle: the vertices along the cut are duplicated (same
    position, different index), as a scan stitched from two pieces. Still a disk (a slit)."""
    n = 8
    V, F = wavy(n)
    V = list(V)
    j = n // 2
    copies = {}
    for i in range(0, n // 2 + 1):  # the cut runs along row j from the left boundary to x = 1/2
        v = grid_index(n, i, j)
        if i == n // 2:
            break  # the tip of the slit stays one vertex
        copies[v] = len(V)
        V.append(V[v])
    newF = []
    for f in F:
        cy = sum(V[u][1] for u in f) / 3
        if cy > j / n:  # faces above the cut use the copies
            newF.append([copies.get(u, u) for u in f])
        else:
            newF.append(list(f))
    return V, newF


def triangle_soup():
    """Every face with its own three vertices (an STL-like soup): many components."""
    V0, F0 = grid(3)
    V, F = [], []
    for f in F0:
        F.append([len(V), len(V) + 1, len(V) + 2])
        V += [V0[u] for u in f]
    return V, F


def unreferenced_vertices():
    V, F = wavy(6)
    return V + [(7.0, 7.0, 7.0), (float("nan"), 0.0, 0.0), (1e30, -1e30, 0.0)], F


def nan_vertex():
    V, F = wavy(6)
    V = list(V)
    V[grid_index(6, 3, 3)] = (float("nan"), 0.5, 0.0)
    return V, F


def inf_vertex():
    V, F = wavy(6)
    V = list(V)
    V[grid_index(6, 3, 3)] = (0.5, float("inf"), 0.0)
    return V, F


def neg_inf_vertex():
    V, F = wavy(6)
    V = list(V)
    V[grid_index(6, 0, 0)] = (0.0, 0.0, float("-inf"))
    return V, F


def one_triangle():
    return [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.2, 0.9, 0.3)], [[0, 1, 2]]


def no_interior_vertex():
    """A strip of 2 x 5 cells: every vertex on the boundary."""
    return grid(5, sx=5.0, sy=1.0, height=lambda x, y: 0.1 * x * x, m=1)


def offset(mesh, d):
    V, F = mesh
    return [(x + d, y + d, z + d) for x, y, z in V], F


def scaled(mesh, s):
    V, F = mesh
    return [(x * s, y * s, z * s) for x, y, z in V], F


CASES = {
    "closed": closed_octahedron,
    "annulus": annulus,
    "two_holes": two_holes,
    "two_components": two_components,
    "nonmanifold_edge": nonmanifold_edge,
    "nonmanifold_vertex": nonmanifold_vertex,
    "bowtie": bowtie,
    "duplicate_face": duplicate_face,
    "duplicate_face_rotated": duplicate_face_rotated,
    "duplicate_face_reversed": duplicate_face_reversed,
    "inconsistent_orientation": inconsistent_orientation,
    "quads": quads,
    "zero_area": zero_area,
    "needles": needles,
    "needle_fan": needle_fan,
    "duplicate_vertex_unused": duplicate_vertex_unused,
    "duplicate_vertex_seam": duplicate_vertex_seam,
    "triangle_soup": triangle_soup,
    "unreferenced_vertices": unreferenced_vertices,
    "nan_vertex": nan_vertex,
    "inf_vertex": inf_vertex,
    "neg_inf_vertex": neg_inf_vertex,
    "one_triangle": one_triangle,
    "no_interior_vertex": no_interior_vertex,
    "wavy": wavy,
    "offset_1e6": lambda: offset(wavy(), 1e6),
    "scaled_1e-6": lambda: scaled(wavy(), 1e-6),
}


def format_number(x):
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(float(x))  # shortest round-trip form: the file holds the exact double


def off_text(mesh):
    V, F = mesh
    lines = ["OFF", f"{len(V)} {len(F)} 0"]
    lines += [" ".join(format_number(c) for c in p) for p in V]
    lines += [" ".join(str(x) for x in [len(f)] + list(f)) for f in F]
    return "\n".join(lines) + "\n"


def write_off(path, mesh):
    with open(path, "w") as out:
        out.write(off_text(mesh))
    return path


def write_case(name, folder):
    os.makedirs(folder, exist_ok=True)
    return write_off(os.path.join(folder, name + ".off"), CASES[name]())


if __name__ == "__main__":
    import sys

    folder = sys.argv[1] if len(sys.argv) > 1 else "."
    for name in (sys.argv[2:] or CASES):
        print(write_case(name, folder))


# The one-line reason each refused case must give, word for word, in every front end (CLI,
# meshlabserver, pymeshlab); shared so that a change of wording is made once.
REFUSED_REASONS = {
    "closed": "the mesh is closed (it has no boundary); cut it open into a disk-shaped patch first, or use the atlas filter (Straightest Distances Atlas; --atlas in the CLI)",
    "two_components":
        "the mesh has 2 connected components; a patch must be one piece (select one component, or use the atlas filter: Straightest Distances Atlas; --atlas in the CLI)",
    "bowtie":
        "the mesh has 2 connected components; a patch must be one piece (select one component, or use the atlas filter: Straightest Distances Atlas; --atlas in the CLI)",
    "triangle_soup":
        "the mesh has 18 connected components: its faces share no edges (merge duplicate "
        "vertices first)",
    "nonmanifold_edge": "edge (6, 12) is shared by more than two faces (a non-manifold edge)",
    "nonmanifold_vertex":
        "vertex 12 is non-manifold (two parts of the surface meet only at this vertex)",
    "duplicate_face": "faces 9 and 32 are duplicates",
    "duplicate_face_rotated": "faces 9 and 32 are duplicates",
    "duplicate_face_reversed": "edge (6, 10) is shared by more than two faces (a non-manifold edge)",
    "inconsistent_orientation": "faces 8 and 9 are oriented inconsistently at edge (6, 10)",
    "nan_vertex": "vertex 24 has a non-finite coordinate (NaN or infinity)",
    "inf_vertex": "vertex 24 has a non-finite coordinate (NaN or infinity)",
    "neg_inf_vertex": "vertex 0 has a non-finite coordinate (NaN or infinity)",
}
