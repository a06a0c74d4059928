"""Scan-like meshes made from whole models, as scanners hand them over before any cleaning: dense
(1-to-4 midpoint subdivision), noisy at the scale of single faces, with small holes and floating
debris, and vertex colours to bake. Seeded: the same arguments give the same mesh, and a mesh
with noise and its twin without (sigma = 0) share their holes and debris.

    make_scan(V, F, subdivisions, sigma, holes, debris, seed) -> (V, F, colours)
    write_ply(path, V, F, colours)       binary PLY, float positions, uchar colours

numpy and the atlas bench's subdivision (bench/atlas.py); used by bench/scans.py."""
import numpy as np

from atlas import subdivide  # 1-to-4 midpoint subdivision, as the atlas bench's big model


def vertex_normals(V, F):
    """Area-weighted vertex normals."""
    n = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    normals = np.zeros_like(V)
    for k in range(3):
        np.add.at(normals, F[:, k], n)
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    return normals / np.where(length > 0, length, 1)


def mean_edge(V, F):
    return float(np.mean(np.linalg.norm(V[F[:, [1, 2, 0]]] - V[F], axis=2)))


def punch_holes(F, vertex_count, holes, rng):
    """Removes `holes` random faces with every face at their vertices (small holes, as a scanner
    leaves where it saw nothing)."""
    if holes <= 0:
        return F
    seeds = rng.choice(len(F), size=min(holes, len(F)), replace=False)
    gone_vertex = np.zeros(vertex_count, dtype=bool)
    gone_vertex[F[seeds].ravel()] = True
    return F[~gone_vertex[F].any(axis=1)]


def debris(V, count, edge, rng):
    """`count` two-triangle quads about 3 edge lengths across, at random places and orientations
    in the bounding box: (V, F) of the debris alone."""
    if count <= 0:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    low, high = V.min(axis=0), V.max(axis=0)
    centres = low + rng.random((count, 3)) * (high - low)
    u = rng.normal(size=(count, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    w = np.cross(u, rng.normal(size=(count, 3)))
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    half = 1.5 * edge
    corners = np.stack([centres + half * (su * u + sw * w)
                        for su, sw in ((-1, -1), (1, -1), (1, 1), (-1, 1))], axis=1)
    base = 4 * np.arange(count)[:, None]
    faces = np.concatenate([base + [0, 1, 2], base + [0, 2, 3]])
    return corners.reshape(-1, 3), faces.astype(np.int64)


def colours_of(V):
    """Smooth sine bands over the bounding box, three per axis, as RGB bytes."""
    low, high = V.min(axis=0), V.max(axis=0)
    t = (V - low) / np.where(high > low, high - low, 1)
    return (127.5 + 127.5 * np.sin(2 * np.pi * 3 * t)).round().astype(np.uint8)


def make_scan(V, F, subdivisions, sigma, holes, debris_count, seed):
    """The scan-like mesh: subdivided, noise along the normals (sigma x the mean edge length),
    holes punched, debris added, vertices used by no face dropped. The random draws for holes
    and debris come from their own streams, so sigma does not move them."""
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    for _ in range(subdivisions):
        V, F = subdivide(V, F)
    F = F.astype(np.int64)
    edge = mean_edge(V, F)
    noise_rng, hole_rng, debris_rng = (np.random.default_rng([seed, k]) for k in range(3))
    if sigma > 0:
        V = V + vertex_normals(V, F) * (sigma * edge * noise_rng.standard_normal(len(V)))[:, None]
    F = punch_holes(F, len(V), holes, hole_rng)
    used = np.zeros(len(V), dtype=bool)
    used[F.ravel()] = True
    renumber = np.cumsum(used) - 1
    V, F = V[used], renumber[F]
    DV, DF = debris(V, debris_count, edge, debris_rng)
    V = np.concatenate([V, DV])
    F = np.concatenate([F, DF + (len(V) - len(DV))])
    return V, F, colours_of(V)


def write_ply(path, V, F, colours):
    with open(path, "wb") as out:
        out.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {len(V)}\n"
                   "property float x\nproperty float y\nproperty float z\n"
                   "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                   f"element face {len(F)}\nproperty list uchar int vertex_indices\n"
                   "end_header\n").encode())
        vertices = np.zeros(len(V), dtype=[("p", "<f4", (3,)), ("c", "u1", (3,))])
        vertices["p"] = V
        vertices["c"] = colours
        out.write(vertices.tobytes())
        faces = np.zeros(len(F), dtype=[("n", "u1"), ("i", "<i4", (3,))])
        faces["n"] = 3
        faces["i"] = F
        out.write(faces.tobytes())
