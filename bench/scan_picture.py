#!/usr/bin/env python3
"""A picture of a multi-million-face atlas: the checkerboard on the model and the UV layout, from
the float PLY the CLI writes (per-face `texcoord` lists and `chart` ids).

    .venv/bin/python bench/scan_picture.py RESULT.ply OUT.png [--title TEXT]

At millions of faces a face is smaller than a pixel of the picture, so both halves are drawn by
splatting each face's centroid (numpy only, seconds at 13M faces) rather than by rasterizing
triangles one at a time as bench/render.py does for the small models: nearest to the viewer wins
on the model, and on the layout each chart gets a colour of its own. Used by bench/scans.py."""
import argparse
import pathlib

import numpy as np

from render import checker_colour, view_frame


def read_atlas_ply(path):
    """Vertices (n x 3), faces (m x 3), per-corner UVs (m x 3 x 2) and chart ids (m) of the binary
    PLY straightest_param writes: double positions, then per face its 3 indices, 6 texcoord
    floats and a chart id."""
    data = pathlib.Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().splitlines()
    counts = {line.split()[1]: int(line.split()[2]) for line in header
              if line.startswith("element")}
    expected = ["property double x", "property double y", "property double z",
                "property list uchar int vertex_indices", "property list uchar float texcoord",
                "property int chart"]
    if [line for line in header if line.startswith("property")] != expected:
        raise ValueError(f"{path}: not the layout straightest_param writes")
    vertex_bytes = 24 * counts["vertex"]
    V = np.frombuffer(data, dtype="<f8", count=3 * counts["vertex"], offset=end).reshape(-1, 3)
    face = np.dtype([("n", "u1"), ("i", "<i4", (3,)), ("t", "u1"), ("uv", "<f4", (6,)),
                     ("chart", "<i4")])
    faces = np.frombuffer(data, dtype=face, count=counts["face"], offset=end + vertex_bytes)
    if (faces["n"] != 3).any() or (faces["t"] != 6).any():
        raise ValueError(f"{path}: faces that are not triangles with 6 texcoords")
    return V, faces["i"], faces["uv"].reshape(-1, 3, 2).astype(np.float64), faces["chart"]


def splat_model(V, F, uv, size, checkers):
    """The checkerboard on the model, seen along its least spread, lit from the front."""
    x, y, z = view_frame(V)
    centre = lambda a: a[F].mean(1)
    cx, cy, cz = centre(x), centre(y), centre(z)
    normal = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    _, _, axes = np.linalg.svd(V - V.mean(0), full_matrices=False)
    # Seen from the side most faces face (as bench/render.py chooses it).
    if (normal @ axes[2]).sum() < 0:
        cx, cz = -cx, -cz
        axes = -axes
    light = axes[2] + 0.4 * axes[1] + 0.2 * axes[0]
    lambert = np.abs(normal @ (light / np.linalg.norm(light)))
    lambert /= np.linalg.norm(normal, axis=1) + 1e-300
    span = max(np.ptp(cx), np.ptp(cy))
    scale = size * 0.94 / span
    px = ((cx - cx.min()) * scale + (size - np.ptp(cx) * scale) / 2).astype(int).clip(0, size - 1)
    py = ((cy.max() - cy) * scale + (size - np.ptp(cy) * scale) / 2).astype(int).clip(0, size - 1)
    colour = checker_colour(uv.mean(1)[None], checkers)[0] * (0.35 + 0.65 * lambert)[:, None]
    image = np.ones((size, size, 3))
    order = np.argsort(cz, kind="stable")  # farthest first: the nearest face is written last
    image[py[order], px[order]] = colour[order]
    return image


def splat_layout(uv, chart, size):
    """The texture square with each chart in a colour of its own (white: unused)."""
    rng = np.random.default_rng(0)
    palette = 0.25 + 0.6 * rng.random((chart.max() + 1, 3))
    centre = uv.mean(1)
    px = (centre[:, 0] * size).astype(int).clip(0, size - 1)
    py = ((1 - centre[:, 1]) * size).astype(int).clip(0, size - 1)
    image = np.ones((size, size, 3))
    image[py, px] = palette[chart]
    return image


def picture(ply, out_png, title=""):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    V, F, uv, chart = read_atlas_ply(ply)
    # A face's centroid per pixel, about: fewer pixels than faces leave no gaps in the charts.
    layout_size = int(np.clip(np.sqrt(len(F) / 3), 256, 2048))
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.6))
    axes[0].imshow(splat_model(V, F, uv, 1000, checkers=64))
    axes[0].set_title("checkerboard (64 squares per side of the texture)", fontsize=9)
    axes[1].imshow(splat_layout(uv, chart, layout_size), extent=(0, 1, 0, 1))
    axes[1].set_title(f"UV layout: {chart.max() + 1} charts", fontsize=9)
    for ax in axes:
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle(title or pathlib.Path(ply).name, fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png, dpi=100)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("ply")
    parser.add_argument("out_png")
    parser.add_argument("--title", default="")
    args = parser.parse_args()
    picture(args.ply, args.out_png, args.title)


if __name__ == "__main__":
    main()
