#!/usr/bin/env python3
"""Pictures for docs/benchmarks.md, drawn from a result file by a small offscreen rasterizer
(numpy + matplotlib only): the checkerboard on the 3D mesh, the stretch heat map on the 3D mesh,
and the flattened layout.

usage: render.py RESULT.obj OUT.png [--title TEXT]
RESULT.obj is what straightest_param writes (v, vt, f v/vt). The checkerboard is the same
pattern as the attached texture (16 squares per side, red grid lines); stretch is the per-face
Sander L2 of docs/method.md §5, normalized so 1 is isometric, on a log colour scale."""
import argparse

import numpy as np


def read_obj(path):
    vertices, texcoords, faces, face_tex = [], [], [], []
    for line in open(path):
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append([float(x) for x in parts[1:4]])
        elif parts[0] == "vt":
            texcoords.append([float(x) for x in parts[1:3]])
        elif parts[0] == "f":
            corners = [p.split("/") for p in parts[1:4]]
            faces.append([int(c[0]) - 1 for c in corners])
            face_tex.append([int(c[1]) - 1 for c in corners])
    return np.array(vertices), np.array(texcoords), np.array(faces), np.array(face_tex)


def face_stretch(q, uv):
    """Per-face normalized L2 stretch (q: F x 3 x 3 corners, uv: F x 3 x 2)."""
    s, t = uv[..., 0], uv[..., 1]
    area2 = 0.5 * ((s[:, 1] - s[:, 0]) * (t[:, 2] - t[:, 0]) - (s[:, 2] - s[:, 0]) * (t[:, 1] - t[:, 0]))
    area3 = 0.5 * np.linalg.norm(np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), axis=1)
    ss = (q[:, 0] * (t[:, 1] - t[:, 2])[:, None] + q[:, 1] * (t[:, 2] - t[:, 0])[:, None] +
          q[:, 2] * (t[:, 0] - t[:, 1])[:, None]) / (2 * area2[:, None])
    st = (q[:, 0] * (s[:, 2] - s[:, 1])[:, None] + q[:, 1] * (s[:, 0] - s[:, 2])[:, None] +
          q[:, 2] * (s[:, 1] - s[:, 0])[:, None]) / (2 * area2[:, None])
    l2 = np.sqrt(0.5 * ((ss * ss).sum(1) + (st * st).sum(1)))
    return l2 * np.sqrt(abs(area2.sum()) / area3.sum())


def view_frame(vertices):
    """Look along the direction of least spread (a patch is seen face on)."""
    centred = vertices - vertices.mean(0)
    _, _, axes = np.linalg.svd(centred, full_matrices=False)
    right, up, forward = axes[0], axes[1], axes[2]
    return centred @ right, centred @ up, centred @ forward


def rasterize(vertices, faces, size):
    """Face index and barycentric coordinates per pixel (z-buffered, orthographic)."""
    x, y, z = view_frame(vertices)
    # Face the camera: most triangle normals should point towards the viewer.
    pts = np.stack([x, y], 1)
    e1, e2 = pts[faces[:, 1]] - pts[faces[:, 0]], pts[faces[:, 2]] - pts[faces[:, 0]]
    signed = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    if signed.sum() < 0:
        x, z = -x, -z
        pts = np.stack([x, y], 1)
    span = max(np.ptp(x), np.ptp(y))
    scale = (size * 0.94) / span
    px = (x - x.min()) * scale + (size - np.ptp(x) * scale) / 2
    py = (y.max() - y) * scale + (size - np.ptp(y) * scale) / 2
    face_id = -np.ones((size, size), dtype=np.int64)
    bary = np.zeros((size, size, 3))
    zbuf = np.full((size, size), -np.inf)
    for f, (a, b, c) in enumerate(faces):
        xs, ys = px[[a, b, c]], py[[a, b, c]]
        x0, x1 = int(max(np.floor(xs.min()), 0)), int(min(np.ceil(xs.max()), size - 1))
        y0, y1 = int(max(np.floor(ys.min()), 0)), int(min(np.ceil(ys.max()), size - 1))
        if x1 < x0 or y1 < y0:
            continue
        gx, gy = np.meshgrid(np.arange(x0, x1 + 1) + 0.5, np.arange(y0, y1 + 1) + 0.5)
        det = (ys[1] - ys[2]) * (xs[0] - xs[2]) + (xs[2] - xs[1]) * (ys[0] - ys[2])
        if abs(det) < 1e-12:
            continue
        l0 = ((ys[1] - ys[2]) * (gx - xs[2]) + (xs[2] - xs[1]) * (gy - ys[2])) / det
        l1 = ((ys[2] - ys[0]) * (gx - xs[2]) + (xs[0] - xs[2]) * (gy - ys[2])) / det
        l2 = 1 - l0 - l1
        inside = (l0 >= 0) & (l1 >= 0) & (l2 >= 0)
        depth = l0 * z[a] + l1 * z[b] + l2 * z[c]
        region = zbuf[y0:y1 + 1, x0:x1 + 1]
        take = inside & (depth > region)
        region[take] = depth[take]
        face_id[y0:y1 + 1, x0:x1 + 1][take] = f
        bary[y0:y1 + 1, x0:x1 + 1][take] = np.stack([l0, l1, l2], -1)[take]
    return face_id, bary


def shade(vertices, faces, face_id):
    n = np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]])
    n /= np.linalg.norm(n, axis=1, keepdims=True) + 1e-300
    _, _, axes = np.linalg.svd(vertices - vertices.mean(0), full_matrices=False)
    light = axes[2] + 0.4 * axes[1] + 0.2 * axes[0]
    light /= np.linalg.norm(light)
    lambert = np.abs(n @ light)
    return 0.35 + 0.65 * lambert[np.maximum(face_id, 0)]


def checker_colour(uv, checkers=16):
    cells = np.floor(uv * checkers).astype(int)
    dark = (cells[..., 0] + cells[..., 1]) % 2 == 1
    colour = np.where(dark[..., None], 40 / 255, 235 / 255) * np.ones(3)
    line = np.minimum(*(np.abs(uv * checkers - np.round(uv * checkers)).transpose(2, 0, 1))) < 0.04
    colour[line] = [200 / 255, 40 / 255, 40 / 255]
    return colour


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("obj")
    parser.add_argument("png")
    parser.add_argument("--title", default="")
    parser.add_argument("--size", type=int, default=420)
    args = parser.parse_args()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import LogNorm

    vertices, texcoords, faces, face_tex = read_obj(args.obj)
    uv_corners = texcoords[face_tex]
    low, high = uv_corners.reshape(-1, 2).min(0), uv_corners.reshape(-1, 2).max(0)
    uv_unit = (uv_corners - low) / (high - low).max()
    stretch = face_stretch(vertices[faces], uv_corners)

    face_id, bary = rasterize(vertices, faces, args.size)
    covered = face_id >= 0
    light = shade(vertices, faces, face_id)[..., None]
    pixel_uv = np.einsum("hwk,hwkd->hwd", bary, uv_unit[np.maximum(face_id, 0)])
    checker = checker_colour(pixel_uv) * light
    checker[~covered] = 1.0
    norm = LogNorm(vmin=1.0, vmax=max(2.0, float(np.percentile(stretch, 99.5))))
    heat = plt.get_cmap("magma_r")(norm(np.clip(stretch, 1.0, None)))[:, :3]
    heat_img = heat[np.maximum(face_id, 0)] * light
    heat_img[~covered] = 1.0

    fig, axes = plt.subplots(1, 3, figsize=(12, 4.3), dpi=100)
    axes[0].imshow(np.clip(checker, 0, 1))
    axes[0].set_title("checkerboard on the mesh")
    axes[1].imshow(np.clip(heat_img, 0, 1))
    axes[1].set_title("stretch per face (1 = none)")
    polys = PolyCollection(uv_unit, array=np.clip(stretch, 1.0, None), cmap="magma_r", norm=norm,
                           edgecolors="none")
    axes[2].add_collection(polys)
    axes[2].set_xlim(-0.02, 1.02)
    axes[2].set_ylim(-0.02, 1.02)
    axes[2].set_aspect("equal")
    axes[2].set_title("flattened layout")
    fig.colorbar(polys, ax=axes[2], fraction=0.046, pad=0.04)
    for ax in axes[:2]:
        ax.axis("off")
    axes[2].set_xticks([])
    axes[2].set_yticks([])
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout(rect=(0, 0, 1, 0.93) if args.title else (0, 0, 1, 1))
    fig.savefig(args.png)


if __name__ == "__main__":
    main()
