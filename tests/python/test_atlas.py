"""The atlas filter in pymeshlab 2025.7 with our plugin: closed, higher-genus and many-piece
meshes get per-wedge UVs in [0,1]^2 with no flipped face, the per-face attribute `chart`, the
report dict; the mesh keeps its vertices, faces, colours and selection; bad input is refused
with one line and the mesh untouched; a batch of good and bad meshes runs in one process; and
MeshLab's own texture baking (Transfer: Vertex Attributes to Texture) on the atlas gives back
the vertex colours."""
import shutil

import numpy as np
import pytest

from conftest import SHARED, run_guarded

ATLAS = "compute_texcoord_parametrization_straightest_distances_atlas"
SUMMARY = ["charts", "seam", "packing_efficiency", "l2_stretch", "linf_stretch", "flipped_faces",
           "overlapping_charts", "seconds", "faces_against_chart", "polygons_as_triangles"]


@pytest.fixture(scope="module")
def atlas_ml(ml):
    if not hasattr(ml.MeshSet, ATLAS):
        setattr(ml.MeshSet, ATLAS, ml.bind_function(ATLAS))
    return ml


def run_atlas(ms, **parameters):
    parameters.setdefault("texturename", "atlas_test.png")
    parameters.setdefault("texturesize", 512)
    return run_guarded(ms, ATLAS, **parameters)


def wedge_uv(mesh):
    return np.array(mesh.wedge_tex_coord_matrix()).reshape(-1, 3, 2)


def expect_certified(mesh, report):
    for key in SUMMARY:
        assert key in report, report
    assert report["flipped_faces"] == 0
    assert report["overlapping_charts"] == 0
    assert report["l2_stretch"] <= 1.05
    uv = wedge_uv(mesh)
    assert uv.min() >= 0 and uv.max() <= 1
    chart = np.array(mesh.face_custom_scalar_attribute_array("chart"))
    assert chart.shape == (mesh.face_number(),)
    assert chart.min() >= 0 and len(np.unique(chart)) == report["charts"]
    # Every face counter-clockwise in its chart: positive signed UV area; but the faces wound
    # against their neighbours, charted turned over, which run clockwise (none degenerate).
    e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    areas = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    assert (areas != 0).all()
    assert int((areas < 0).sum()) == report["faces_against_chart"]


def test_closed_sphere_with_colours_and_selection_kept(atlas_ml):
    ms = atlas_ml.MeshSet()
    ms.create_sphere(subdiv=4)
    ms.compute_color_by_function_per_vertex(x="(x+1)*127", y="(y+1)*127", z="(z+1)*127")
    ms.compute_selection_by_condition_per_face(condselect="x0 > 0.5")
    m = ms.current_mesh()
    before = (m.vertex_matrix().copy(), m.face_matrix().copy(), m.vertex_color_matrix().copy(),
              m.face_selection_array().copy())
    report = run_atlas(ms)
    m = ms.current_mesh()
    expect_certified(m, report)
    assert report["charts"] >= 2
    after = (m.vertex_matrix(), m.face_matrix(), m.vertex_color_matrix(), m.face_selection_array())
    for a, b in zip(before, after):
        assert np.array_equal(a, b)


def test_selected_faces_only(atlas_ml):
    ms = atlas_ml.MeshSet()
    ms.create_sphere(subdiv=3)
    ms.compute_selection_by_condition_per_face(condselect="z0 > 0 && z1 > 0 && z2 > 0")
    m = ms.current_mesh()
    selected = np.array(m.face_selection_array(), dtype=bool)
    report = run_atlas(ms, selectedonly=True)
    chart = np.array(ms.current_mesh().face_custom_scalar_attribute_array("chart"))
    assert (chart[selected] >= 0).all() and (chart[~selected] == -1).all()
    assert report["flipped_faces"] == 0


def test_shared_closed_models(atlas_ml, tmp_path):
    models = [SHARED / "meshes" / "closed" / name
              for name in ("fertility.off", "truck.obj", "horse_quad.obj")]
    models = [path for path in models if path.exists()]
    if not models:
        pytest.skip("the shared closed models are not beside the clone")
    for path in models:
        # The texture is written next to the mesh: a copy keeps the shared folder as it was.
        copy = tmp_path / path.name
        shutil.copyfile(path, copy)
        ms = atlas_ml.MeshSet()
        ms.load_new_mesh(str(copy))
        expect_certified(ms.current_mesh(), run_atlas(ms))


def test_bad_input_refused_with_one_line_and_mesh_untouched(atlas_ml):
    ms = atlas_ml.MeshSet()
    ms.add_mesh(atlas_ml.Mesh(vertex_matrix=np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0]]),
                              face_matrix=np.array([[0, 1, 2]], dtype=np.int32)))
    with pytest.raises(atlas_ml.PyMeshLabException) as error:
        run_atlas(ms)
    reason = str(error.value).split("Details:", 1)[-1].strip()
    assert reason == "every face has zero area (no surface to flatten)"
    assert not ms.current_mesh().has_wedge_tex_coord()
    with pytest.raises(atlas_ml.PyMeshLabException) as error:
        run_atlas(ms, gutter=1000)
    assert "gutter" in str(error.value)


def test_batch_of_good_and_bad_meshes_in_one_process(atlas_ml):
    flat = (np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0]]), np.array([[0, 1, 2]]))
    results = []
    for round_ in range(3):
        for good in (True, False, True):
            ms = atlas_ml.MeshSet()
            if good:
                ms.create_sphere(subdiv=2 + round_ % 2)
            else:
                ms.add_mesh(atlas_ml.Mesh(vertex_matrix=flat[0],
                                          face_matrix=flat[1].astype(np.int32)))
            try:
                results.append(run_atlas(ms)["flipped_faces"])
            except atlas_ml.PyMeshLabException:
                results.append("refused")
    assert results == [0, "refused", 0] * 3


def test_baking_vertex_colours_into_the_atlas_texture(atlas_ml, tmp_path):
    """MeshLab's Transfer: Vertex Attributes to Texture on our atlas, read back by MeshLab's
    Transfer: Texture to Vertex Colour, gives the colours the mesh had."""
    ms = atlas_ml.MeshSet()
    ms.create_sphere(subdiv=4)
    ms.compute_color_by_function_per_vertex(x="(x+1)*127", y="(y+1)*127", z="(z+1)*127")
    colours = ms.current_mesh().vertex_color_matrix().copy()
    run_atlas(ms, texturesize=1024)
    ms.transfer_attributes_to_texture_per_vertex(sourcemesh=0, targetmesh=0,
                                                 textname=str(tmp_path / "baked.png"),
                                                 textw=1024, texth=1024)
    ms.transfer_texture_to_color_per_vertex()
    difference = np.abs(ms.current_mesh().vertex_color_matrix() - colours)[:, :3] * 255
    assert difference.mean() < 2 and difference.max() <= 4
