"""Numpy versions of the docs/method.md section 5 measures, computed from what pymeshlab hands back."""
import numpy as np


def signed_uv_areas(uv_corners):
    """uv_corners: (F, 3, 2) -> (F,) signed areas (positive = counter-clockwise)."""
    e1 = uv_corners[:, 1] - uv_corners[:, 0]
    e2 = uv_corners[:, 2] - uv_corners[:, 0]
    return 0.5 * (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])


def non_positive_faces(uv_corners):
    """Faces flipped or degenerate under the orientation the core guarantees (area > 0)."""
    return int(np.count_nonzero(signed_uv_areas(uv_corners) <= 0))


def folded_faces(uv_corners):
    """Faces against the map's majority orientation, or degenerate: for peers whose maps may be
    mirrored as a whole (a mirror is not a fold)."""
    areas = signed_uv_areas(uv_corners)
    orientation = 1.0 if areas.sum() >= 0 else -1.0
    return int(np.count_nonzero(areas * orientation <= 0))


def sander_stretch(positions, uv_corners):
    """Sander et al. 2001 L2 and L-infinity stretch, normalized so 1.0 is isometric.

    positions: (F, 3, 3) corner positions; uv_corners: (F, 3, 2). Uses |A2| so that a globally
    mirrored map measures like its mirror image.
    """
    q1, q2, q3 = positions[:, 0], positions[:, 1], positions[:, 2]
    s1, s2, s3 = uv_corners[:, 0, 0], uv_corners[:, 1, 0], uv_corners[:, 2, 0]
    t1, t2, t3 = uv_corners[:, 0, 1], uv_corners[:, 1, 1], uv_corners[:, 2, 1]
    area2 = ((s2 - s1) * (t3 - t1) - (s3 - s1) * (t2 - t1)) / 2.0
    with np.errstate(divide="ignore", invalid="ignore"):
        ss = (q1 * (t2 - t3)[:, None] + q2 * (t3 - t1)[:, None] + q3 * (t1 - t2)[:, None]) / (
            2.0 * area2[:, None])
        st = (q1 * (s3 - s2)[:, None] + q2 * (s1 - s3)[:, None] + q3 * (s2 - s1)[:, None]) / (
            2.0 * area2[:, None])
    a = np.einsum("ij,ij->i", ss, ss)
    b = np.einsum("ij,ij->i", ss, st)
    c = np.einsum("ij,ij->i", st, st)
    area3 = 0.5 * np.linalg.norm(np.cross(q2 - q1, q3 - q1), axis=1)
    l2_face_sq = (a + c) / 2.0
    linf_face = np.sqrt(((a + c) + np.sqrt((a - c) ** 2 + 4.0 * b * b)) / 2.0)
    scale = np.sqrt(np.abs(area2).sum() / area3.sum())
    l2 = np.sqrt((l2_face_sq * area3).sum() / area3.sum()) * scale
    linf = linf_face.max() * scale
    return float(l2), float(linf)


def wedge_uv_corners(mesh):
    """(F, 3, 2) per-wedge UVs of a pymeshlab Mesh."""
    return np.asarray(mesh.wedge_tex_coord_matrix(), dtype=float).reshape(-1, 3, 2)


def vertex_uv_corners(mesh):
    """(F, 3, 2) per-vertex UVs of a pymeshlab Mesh, gathered per face corner."""
    uv = np.asarray(mesh.vertex_tex_coord_matrix(), dtype=float)
    return uv[np.asarray(mesh.face_matrix())]


def corner_positions(mesh):
    return np.asarray(mesh.vertex_matrix(), dtype=float)[np.asarray(mesh.face_matrix())]
