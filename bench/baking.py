#!/usr/bin/env python3
"""MeshLab's own texture baking on our atlas, as a pymeshlab user runs it: a mesh with vertex
colours (pymeshlab's sample `colored_airplane.ply`), our atlas filter, then MeshLab's *Transfer:
Vertex Attributes to Texture (1 or 2 meshes)*. The picture shows the vertex colours on the mesh,
the baked texture, and the mesh rendered with that texture; the numbers compare the colours
read back from the texture (MeshLab's *Transfer: Texture to Vertex Color*) with the originals.

usage: .venv/bin/python bench/baking.py [--build build] [--size 1024] [--doc docs/benchmarks.md]
Writes bench/results/baking.png and bench/results/baking.md (and, with --doc, that file's
bench:baking block)."""
import argparse
import pathlib
import tempfile

import numpy as np

import render
from run import DOC, replace_block, results_link

HERE = pathlib.Path(__file__).resolve().parent
REPO = HERE.parent
ATLAS = "compute_texcoord_parametrization_straightest_distances_atlas"


def load_pymeshlab(plugin):
    import pymeshlab
    if ATLAS not in pymeshlab.filter_list():
        pymeshlab.load_plugin(str(plugin))
    if not hasattr(pymeshlab.MeshSet, ATLAS):
        setattr(pymeshlab.MeshSet, ATLAS, pymeshlab.bind_function(ATLAS))
    return pymeshlab


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", type=pathlib.Path, default=REPO / "build")
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--doc", type=pathlib.Path,
                        help="the file holding the bench:baking block (docs/benchmarks.md)")
    args = parser.parse_args()
    plugin = args.build / "plugins" / "meshlab-2025.07" / "libfilter_straightest_param.so"
    ml = load_pymeshlab(plugin)
    source = (pathlib.Path(ml.__file__).parent / "tests" / "sample_meshes" /
              "colored_airplane.ply")
    work = pathlib.Path(tempfile.mkdtemp(prefix="baking-"))
    ms = ml.MeshSet()
    ms.load_new_mesh(str(source))
    mesh = ms.current_mesh()
    vertices = mesh.vertex_matrix().copy()
    faces = mesh.face_matrix().copy()
    colours = mesh.vertex_color_matrix()[:, :3].copy()
    report = getattr(ms, ATLAS)(texturesize=args.size, texturename="atlas.png")
    uv = np.array(ms.current_mesh().wedge_tex_coord_matrix()).reshape(-1, 3, 2)
    baked = work / "baked.png"
    ms.transfer_attributes_to_texture_per_vertex(sourcemesh=0, targetmesh=0,
                                                 textname=baked.name, textw=args.size,
                                                 texth=args.size)
    # MeshLab 2025.07 keeps the baked image in the mesh; saving the mesh writes it out.
    ms.save_current_mesh(str(work / "baked.obj"))
    ms.transfer_texture_to_color_per_vertex()
    back = ms.current_mesh().vertex_color_matrix()[:, :3]
    # Vertices no face uses have no texture to take a colour from (the sample has 1617).
    used = np.zeros(len(vertices), dtype=bool)
    used[faces.ravel()] = True
    difference = np.abs(back - colours)[used] * 255

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt
    texture = mpimg.imread(str(baked))[..., :3]
    face_id, bary = render.rasterize(vertices, faces, 400)
    covered = face_id >= 0
    f = np.maximum(face_id, 0)
    light = render.shade(vertices, faces, face_id)[..., None]
    vertex_view = np.einsum("hwk,hwkc->hwc", bary, colours[faces[f]]) * light
    pixel_uv = np.einsum("hwk,hwkd->hwd", bary, uv[f])
    h, w = texture.shape[:2]
    # Texture row 0 is the image's top; v = 0 is its bottom.
    tx = np.clip((pixel_uv[..., 0] * w).astype(int), 0, w - 1)
    ty = np.clip(((1 - pixel_uv[..., 1]) * h).astype(int), 0, h - 1)
    texture_view = texture[ty, tx] * light
    for image in (vertex_view, texture_view):
        image[~covered] = 1.0
    fig, axes = plt.subplots(1, 3, figsize=(10.5, 3.8))
    titles = ["vertex colours on the mesh", f"baked texture ({args.size}², {report['charts']} "
              "charts)", "the mesh with the baked texture"]
    for ax, image, title in zip(axes, (vertex_view, texture, texture_view), titles):
        ax.imshow(np.clip(image, 0, 1))
        ax.set_title(title, fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    results = REPO / "bench" / "results"
    fig.savefig(results / "baking.png", dpi=100)
    plt.close(fig)
    body = (
        f"pymeshlab's `colored_airplane.ply` ({len(vertices)} vertices, {len(faces)} faces, "
        f"vertex colours): our atlas at {args.size}² ({report['charts']} charts, L2 "
        f"{report['l2_stretch']:.4f}, efficiency {report['packing_efficiency']:.3f}), then "
        "MeshLab's *Transfer: Vertex Attributes to Texture (1 or 2 meshes)* into a "
        f"{args.size}² texture. Read back by *Transfer: Texture to Vertex Color*, the colours "
        f"of the {used.sum()} vertices that faces use differ from the originals by "
        f"{difference.mean():.2f} of 255 on average (largest {difference.max():.0f}; the "
        f"other {len(vertices) - used.sum()} vertices belong to no face). Made by "
        "`.venv/bin/python bench/baking.py --doc "
        "docs/benchmarks.md`.\n\n![vertex colours, the baked texture, the textured mesh]")
    # The picture linked from where each file is: beside it in bench/results, ../bench/results
    # from docs/.
    (results / "baking.md").write_text(body + "(baking.png)\n")
    doc_body = body + f"({results_link('baking.png', args.doc or DOC)})\n"
    print(doc_body)
    if args.doc:
        args.doc.write_text(replace_block(args.doc.read_text(), "baking", doc_body))


if __name__ == "__main__":
    main()
