"""Everyday inputs in pymeshlab 2025.7 with our plugin (resources/meshes/inputs, made by
scripts/make-input-meshes.py): polygon meshes keep their map when saved with
save_current_mesh's defaults, STL and tristrip PLY as pymeshlab reads them get an atlas, and a
mesh whose faces are wound at random gets the charts of the consistently wound one."""
import shutil

import numpy as np
import pytest

from conftest import BUNDLED, FILTER, run_guarded

ATLAS = FILTER + "_atlas"
INPUTS = BUNDLED / "inputs"


@pytest.fixture(scope="module")
def atlas_ml(ml):
    if not hasattr(ml.MeshSet, ATLAS):
        setattr(ml.MeshSet, ATLAS, ml.bind_function(ATLAS))
    return ml


def loaded(ml, name, tmp_path, folder=INPUTS):
    """A MeshSet holding a copy of the input (the texture is written next to the mesh)."""
    copy = tmp_path / name
    shutil.copyfile(folder / name, copy)
    ms = ml.MeshSet()
    ms.load_new_mesh(str(copy))
    return ms


def read_obj_uvs(path):
    """Per face the three (u, v) of its corners, from an OBJ's `f v/vt` lines; None where a
    face is not a triangle with texture coordinates."""
    vt, faces = [], []
    for line in open(path):
        parts = line.split()
        if parts and parts[0] == "vt":
            vt.append((float(parts[1]), float(parts[2])))
        elif parts and parts[0] == "f":
            corners = [c.split("/") for c in parts[1:]]
            if len(corners) != 3 or any(len(c) < 2 or not c[1] for c in corners):
                faces.append(None)
            else:
                faces.append([vt[int(c[1]) - 1] for c in corners])
    return faces


def signed_areas(uv):
    e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    return e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]


@pytest.mark.parametrize("name,filter_name", [
    ("cube_quads.off", ATLAS), ("cube_triangles_quads_triangle.off", ATLAS),
    ("prism_hexagons.off", ATLAS), ("torus_quads.off", ATLAS), ("disk_quads.off", FILTER)])
def test_polygon_mesh_saved_with_defaults_keeps_the_map(atlas_ml, tmp_path, name, filter_name):
    ms = loaded(atlas_ml, name, tmp_path)
    report = run_guarded(ms, filter_name, texturesize=512)
    assert report["flipped_faces"] == 0
    assert report["polygons_as_triangles"] is True
    in_memory = np.array(ms.current_mesh().wedge_tex_coord_matrix()).reshape(-1, 3, 2)
    obj = tmp_path / "saved.obj"
    ms.save_current_mesh(str(obj))  # pymeshlab's defaults, as a pipeline writes it
    stored = read_obj_uvs(obj)
    assert None not in stored, "a face was saved without per-wedge texture coordinates"
    stored = np.array(stored)
    # The file holds the map the filter certified (OBJ: 6 decimals), every face counter-clockwise.
    assert stored.shape == in_memory.shape
    assert np.abs(stored - in_memory).max() < 1e-6
    assert (signed_areas(stored) > 0).all()


def test_triangle_mesh_is_not_reported_polygonal(atlas_ml, tmp_path):
    ms = loaded(atlas_ml, "torus_random_winding.off", tmp_path)
    assert run_guarded(ms, ATLAS, texturesize=512)["polygons_as_triangles"] is False


@pytest.mark.parametrize("name", ["torus_binary.stl", "torus_ascii.stl", "torus_tristrips.ply"])
def test_stl_and_tristrips_as_pymeshlab_reads_them(atlas_ml, tmp_path, name):
    ms = loaded(atlas_ml, name, tmp_path)
    assert ms.current_mesh().face_number() == 768
    report = run_guarded(ms, ATLAS, texturesize=512)
    assert report["flipped_faces"] == 0 and report["overlapping_charts"] == 0
    assert report["l2_stretch"] <= 1.05


def test_randomly_wound_faces_get_the_charts_of_the_consistent_mesh(atlas_ml, tmp_path):
    consistent = loaded(atlas_ml, "torus.off", tmp_path, BUNDLED / "closed")
    expected = run_guarded(consistent, ATLAS, texturesize=512)
    ms = loaded(atlas_ml, "torus_random_winding.off", tmp_path)
    faces_before = ms.current_mesh().face_matrix().copy()
    report = run_guarded(ms, ATLAS, texturesize=512)
    assert report["faces_against_chart"] > 0
    assert report["charts"] == expected["charts"]
    assert report["flipped_faces"] == 0
    assert abs(report["l2_stretch"] - expected["l2_stretch"]) < 1e-6
    # The faces keep their own winding; a turned face's UV triangle runs clockwise.
    m = ms.current_mesh()
    assert np.array_equal(m.face_matrix(), faces_before)
    areas = signed_areas(np.array(m.wedge_tex_coord_matrix()).reshape(-1, 3, 2))
    assert int((areas < 0).sum()) == report["faces_against_chart"]
