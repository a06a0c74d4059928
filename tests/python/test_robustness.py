"""The robustness cases (tests/robustness/CASES.md) in pymeshlab 2025.7 with our plugin.

Refused input: PyMeshLabException whose "Details:" is the exact one-line reason, and the mesh
exactly as it was (coordinates, faces, selection, no UVs, no quality, no texture) with no file
written. Flattened input: a report with 0 flipped faces, confirmed from the wedge UVs pymeshlab
hands back (positive area on every face, L2 recomputed in numpy equal to the reported one).
Meshes come from tests/robustness/meshgen.py, the same ones the CLI and meshlabserver cases use.
"""
import math
import os
import pathlib
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import stretch
from conftest import BOUNDARIES, FILTER, PLUGIN, WEIGHTS, run_guarded

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "robustness"))
import meshgen  # noqa: E402

REFUSED = meshgen.REFUSED_REASONS

# case: (holes filled, expect every weight x boundary to work)
FLATTENED = {
    "annulus": 1, "two_holes": 2, "zero_area": 0, "needles": 0, "duplicate_vertex_unused": 0,
    "duplicate_vertex_seam": 0, "unreferenced_vertices": 0, "one_triangle": 0,
    "no_interior_vertex": 0, "wavy": 0,
}


def mesh_set(ml, mesh, name="case"):
    """A MeshSet holding exactly the generated mesh (no importer in between)."""
    V, F = mesh
    ms = ml.MeshSet()
    ms.add_mesh(ml.Mesh(vertex_matrix=np.array(V, dtype=float),
                        face_matrix=np.array(F, dtype=np.int32).reshape(-1, 3)), name)
    return ms


def run_filter(ms, **parameters):
    parameters.setdefault("texturename", "robustness_checker.png")
    return run_guarded(ms, **parameters)


def snapshot(mesh):
    return {
        "vertices": np.array(mesh.vertex_matrix(), copy=True),
        "faces": np.array(mesh.face_matrix(), copy=True),
        "vertex_selection": np.array(mesh.vertex_selection_array(), copy=True),
        "face_selection": np.array(mesh.face_selection_array(), copy=True),
        "wedge_uv": mesh.has_wedge_tex_coord(),
        "face_scalar": mesh.has_face_scalar(),
        "textures": sorted(mesh.textures()),
    }


def assert_unchanged(before, after):
    np.testing.assert_array_equal(before["vertices"], after["vertices"])  # NaN == NaN here
    for key in ("faces", "vertex_selection", "face_selection"):
        np.testing.assert_array_equal(before[key], after[key], err_msg=key)
    for key in ("wedge_uv", "face_scalar", "textures"):
        assert before[key] == after[key], key


def expect_refused(ml, ms, reason, **parameters):
    before = snapshot(ms.current_mesh())
    with pytest.raises(ml.PyMeshLabException) as error:
        run_filter(ms, **parameters)
    message = str(error.value)
    got = message.split("Details:", 1)[-1].strip()
    assert got == reason, message
    assert "\n" not in got
    assert_unchanged(before, snapshot(ms.current_mesh()))
    return got


def expect_flattened(ms, **parameters):
    report = run_filter(ms, **parameters)
    mesh = ms.current_mesh()
    uv = stretch.wedge_uv_corners(mesh)
    assert np.isfinite(uv).all()
    assert report["flipped_faces"] == 0
    assert stretch.non_positive_faces(uv) == 0
    l2, linf = stretch.sander_stretch(stretch.corner_positions(mesh), uv)
    assert math.isclose(report["l2_stretch"], l2, rel_tol=1e-6), (report["l2_stretch"], l2)
    assert math.isclose(report["linf_stretch"], linf, rel_tol=1e-6)
    return report, uv


# --- refused input ---------------------------------------------------------------------------------

@pytest.mark.parametrize("case", list(REFUSED))
def test_refused_with_reason_and_mesh_untouched(ml, case):
    ms = mesh_set(ml, meshgen.CASES[case]())
    expect_refused(ml, ms, REFUSED[case])


@pytest.mark.parametrize("case", ["closed", "two_components", "nonmanifold_vertex"])
def test_refused_mesh_from_a_file_gets_no_texture_file(ml, tmp_path, case):
    path = meshgen.write_case(case, str(tmp_path))
    ms = ml.MeshSet()
    ms.load_new_mesh(path)
    expect_refused(ml, ms, REFUSED[case])
    assert sorted(os.listdir(tmp_path)) == [os.path.basename(path)]


@pytest.mark.parametrize("content", [b"", bytes(range(256)) * 4, b"OFF\n10 10 0\n0 0 0\n"],
                         ids=["empty", "garbage", "truncated"])
def test_unreadable_files_are_refused_by_the_loader(ml, tmp_path, content):
    path = tmp_path / "bad.off"
    path.write_bytes(content)
    ms = ml.MeshSet()
    with pytest.raises(ml.PyMeshLabException):
        ms.load_new_mesh(str(path))
    assert ms.mesh_number() == 0


# --- flattened input -------------------------------------------------------------------------------

@pytest.mark.parametrize("boundary", list(BOUNDARIES))
@pytest.mark.parametrize("case", list(FLATTENED))
def test_flattened_one_to_one(ml, case, boundary):
    ms = mesh_set(ml, meshgen.CASES[case]())
    report, _ = expect_flattened(ms, boundary=BOUNDARIES[boundary])
    assert report["fallbacks"] >= 0


@pytest.mark.parametrize("weights", WEIGHTS)
@pytest.mark.parametrize("case", ["zero_area", "needles", "one_triangle", "no_interior_vertex",
                                  "two_holes"])
def test_degenerate_cases_for_every_weight(ml, case, weights):
    for boundary in BOUNDARIES.values():
        expect_flattened(mesh_set(ml, meshgen.CASES[case]()), weights=weights, boundary=boundary)


def test_quads_are_triangulated_by_meshlab_and_flattened(ml, tmp_path):
    ms = ml.MeshSet()
    ms.load_new_mesh(meshgen.write_case("quads", str(tmp_path)))
    assert ms.current_mesh().face_number() == 32
    expect_flattened(ms)


def test_no_interior_vertex_falls_back_to_the_circle_and_refuses_a_boundary_source(ml):
    ms = mesh_set(ml, meshgen.CASES["no_interior_vertex"]())
    report, _ = expect_flattened(ms)
    assert report["source_vertex"] == -1 and report["fallbacks"] >= 1
    ms = mesh_set(ml, meshgen.CASES["no_interior_vertex"]())
    expect_refused(ml, ms, "source vertex 1 is on the boundary; the measured boundary needs an "
                           "interior vertex", sourcevertex=1)


def test_short_edge_is_repaired_as_stored(ml, tmp_path):
    """A 1e-7 edge: one-to-one in double precision, but MeshLab's float wedge UVs and its OBJ's 6
    decimals would collapse the needle faces. The core repairs the map as stored: no face of
    non-positive area in the mesh nor in the saved OBJ."""
    n = 8
    V, F = meshgen.wavy(n)
    v, w = meshgen.grid_index(n, 4, 4), meshgen.grid_index(n, 5, 4)
    V[v] = tuple(p + (q - p) * (1 - 1e-7) for p, q in zip(V[v], V[w]))
    ms = mesh_set(ml, (V, F))
    report = run_filter(ms)
    assert report["flipped_faces"] == 0
    areas = stretch.signed_uv_areas(stretch.wedge_uv_corners(ms.current_mesh()))
    assert np.all(areas > 0)
    path = tmp_path / "needle.obj"
    ms.save_current_mesh(str(path), save_wedge_texcoord=True)
    vt, corners = [], []
    for line in path.read_text().splitlines():
        if line.startswith("vt "):
            vt.append([float(x) for x in line.split()[1:3]])
        elif line.startswith("f "):
            corners.append([vt[int(c.split("/")[1]) - 1] for c in line.split()[1:4]])
    saved = np.array(corners)
    assert len(saved) == len(F)
    a, b, c = saved[:, 0], saved[:, 1], saved[:, 2]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    assert np.all(cross > 0), f"{np.count_nonzero(cross <= 0)} faces flipped in the saved OBJ"


# --- source vertex ---------------------------------------------------------------------------------

def test_source_vertex_reasons(ml):
    V, F = meshgen.wavy(6)
    mesh = (V + [(9.0, 9.0, 9.0)], F)  # vertex 49: used by no face
    expect_refused(ml, mesh_set(ml, mesh), "source vertex 3 is on the boundary; the measured "
                   "boundary needs an interior vertex", sourcevertex=3)
    expect_refused(ml, mesh_set(ml, mesh), "source vertex 49 is not a vertex of the patch",
                   sourcevertex=49)
    expect_refused(ml, mesh_set(ml, mesh), "source vertex 50 is not a vertex of the patch",
                   sourcevertex=50)
    report, _ = expect_flattened(mesh_set(ml, mesh), sourcevertex=17)
    assert report["source_vertex"] == 17


def test_single_selected_boundary_vertex_is_refused_as_source(ml):
    ms = mesh_set(ml, meshgen.wavy(6))
    ms.compute_selection_by_condition_per_vertex(condselect="(vi == 3)")
    expect_refused(ml, ms, "source vertex 3 is on the boundary; the measured boundary needs an "
                           "interior vertex")


# --- scale and translation -------------------------------------------------------------------------

@pytest.mark.parametrize("boundary", list(BOUNDARIES))
def test_scale_and_translation_invariant(ml, boundary):
    base, base_uv = expect_flattened(mesh_set(ml, meshgen.wavy()), boundary=BOUNDARIES[boundary])
    for case in ("offset_1e6", "scaled_1e-6"):
        report, uv = expect_flattened(mesh_set(ml, meshgen.CASES[case]()),
                                      boundary=BOUNDARIES[boundary])
        for key in ("l2_stretch", "linf_stretch"):
            assert math.isclose(report[key], base[key], rel_tol=1e-6), (case, key)
        assert report["source_vertex"] == base["source_vertex"]
        # Both maps are fitted into the unit square: the same UVs up to float rounding.
        assert np.abs(uv - base_uv).max() < 1e-5, case


# --- selected faces only ---------------------------------------------------------------------------

def test_selectedonly_with_nothing_selected_is_refused(ml):
    ms = mesh_set(ml, meshgen.wavy())
    expect_refused(ml, ms, "no faces are selected", selectedonly=True)


def test_selectedonly_with_two_separate_regions_is_refused(ml):
    ms = mesh_set(ml, meshgen.wavy())
    ms.compute_selection_by_condition_per_face(
        condselect="(x0 < 0.3 && x1 < 0.3 && x2 < 0.3) || (x0 > 0.7 && x1 > 0.7 && x2 > 0.7)")
    assert ms.current_mesh().selected_face_number() > 0
    expect_refused(ml, ms, "the mesh has 2 connected components; a patch must be one piece "
                           "(select one component, or use the atlas filter: Straightest "
                           "Distances Atlas; --atlas in the CLI)", selectedonly=True)


def test_selectedonly_with_a_ring_fills_its_hole(ml):
    ms = mesh_set(ml, meshgen.wavy())
    # Everything but the faces touching the centre vertex: a ring around a hole.
    ms.compute_selection_by_condition_per_face(condselect=" && ".join(
        f"((x{k} - 0.5)^2 + (y{k} - 0.5)^2 > 1e-4)" for k in range(3)))
    report = run_filter(ms, selectedonly=True)
    mesh = ms.current_mesh()
    selected = np.asarray(mesh.face_selection_array())
    uv = stretch.wedge_uv_corners(mesh)[selected]
    assert report["flipped_faces"] == 0 and stretch.non_positive_faces(uv) == 0


def test_selectedonly_with_a_disk_maps_it_like_the_part_alone(ml):
    V, F = meshgen.wavy()
    ms = mesh_set(ml, (V, F))
    whole = run_filter(ms, boundary="Circle")  # every face gets UVs first
    uv_before = stretch.wedge_uv_corners(ms.current_mesh()).copy()
    ms.compute_selection_by_condition_per_face(condselect="(x0 < 0.55 && x1 < 0.55 && x2 < 0.55)")
    selected = np.asarray(ms.current_mesh().face_selection_array()).copy()
    assert 0 < selected.sum() < len(F)
    part = run_filter(ms, selectedonly=True, boundary="Circle")
    uv = stretch.wedge_uv_corners(ms.current_mesh())
    # Faces outside the selection keep the UVs they had.
    np.testing.assert_array_equal(uv[~selected], uv_before[~selected])
    alone = mesh_set(ml, (V, [f for f, s in zip(F, selected) if s]))
    expected, expected_uv = expect_flattened(alone, boundary="Circle")
    assert math.isclose(part["l2_stretch"], expected["l2_stretch"], rel_tol=1e-9)
    np.testing.assert_allclose(uv[selected], expected_uv, atol=1e-6)
    assert whole["l2_stretch"] != part["l2_stretch"]


# --- deleted elements ------------------------------------------------------------------------------

@pytest.mark.parametrize("how", ["faces", "faces_and_vertices", "vertex"])
def test_deleted_elements_give_the_map_of_what_is_left(ml, how):
    """Elements removed by MeshLab filters first: the map equals that of the mesh built without
    them (same L2, same UVs per face)."""
    V, F = meshgen.wavy()
    centre = meshgen.grid_index(8, 4, 4)
    ms = mesh_set(ml, (V, F))
    if how == "vertex":
        ms.compute_selection_by_condition_per_vertex(condselect=f"(vi == {centre})")
        ms.meshing_remove_selected_vertices()
    else:
        ms.compute_selection_by_condition_per_face(condselect=" || ".join(
            f"((x{k} - 0.5)^2 + (y{k} - 0.5)^2 < 1e-4)" for k in range(3)))
        if how == "faces":
            ms.meshing_remove_selected_faces()
        else:
            ms.meshing_remove_selected_vertices_and_faces()
    ms.set_selection_none()
    kept = [f for f in F if centre not in f]
    assert ms.current_mesh().face_number() == len(kept)
    report, uv = expect_flattened(ms)
    expected, expected_uv = expect_flattened(mesh_set(ml, (V, kept)))
    assert math.isclose(report["l2_stretch"], expected["l2_stretch"], rel_tol=1e-9)
    np.testing.assert_allclose(uv, expected_uv, atol=1e-6)
    positions = np.asarray(ms.current_mesh().vertex_matrix())
    source = np.array(V[expected["source_vertex"]])
    np.testing.assert_allclose(positions[report["source_vertex"]], source)


# --- a mesh too large for memory -------------------------------------------------------------------

MEMORY_SCRIPT = textwrap.dedent("""
    import re, resource, sys
    import numpy as np
    import pymeshlab as ml
    FILTER, PLUGIN, LIMIT_MB = sys.argv[1], sys.argv[2], int(sys.argv[3])
    if FILTER not in ml.filter_list():
        ml.load_plugin(PLUGIN)
    run = ml.bind_function(FILTER)
    n = 600  # 361k vertices, 720k faces
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1))
    V = np.stack([i.ravel() / n, j.ravel() / n, 0.2 * np.sin(3 * i.ravel() / n)], axis=1)
    a = (j[:-1, :-1] * (n + 1) + i[:-1, :-1]).ravel()
    F = np.concatenate([np.stack([a, a + 1, a + n + 2], 1), np.stack([a, a + n + 2, a + n + 1], 1)])
    ms = ml.MeshSet()
    ms.add_mesh(ml.Mesh(vertex_matrix=V, face_matrix=F.astype(np.int32)), "big")
    def status(key):
        return int(re.search(key + r":\\s+(\\d+)", open("/proc/self/status").read()).group(1)) << 10
    base = status("VmSize")
    if LIMIT_MB >= 0:  # else: unlimited, and print what the run needed
        resource.setrlimit(resource.RLIMIT_AS, (base + (LIMIT_MB << 20), resource.RLIM_INFINITY))
    try:
        report = run(ms, texturename="robustness_checker.png", boundary="Circle")
        outcome = "success %d" % report["flipped_faces"]
    except ml.PyMeshLabException as e:
        outcome = "refused: " + str(e).split("Details:", 1)[-1].strip()
    except MemoryError:
        outcome = "refused: MemoryError"
    resource.setrlimit(resource.RLIMIT_AS, (resource.RLIM_INFINITY, resource.RLIM_INFINITY))
    if LIMIT_MB < 0:
        print("needs", (status("VmPeak") - base) >> 20)
    print(outcome, "| uv" if ms.current_mesh().has_wedge_tex_coord() else "| no uv", flush=True)
""")


def test_too_large_for_memory_refuses_cleanly_and_never_aborts(ml, tmp_path):
    """The plugin under address-space limits from 2 % to 120 % of what one run needs above what
    Python already uses, each in a fresh Python process (a session's first run also starts the
    OpenMP threads): every run either succeeds or refuses with a reason naming memory and leaves
    the mesh without UVs. An abort (std::terminate, or OpenMP's runtime exiting) would take the
    user's whole Python or MeshLab session with it."""
    def child(limit_mb):
        done = subprocess.run([sys.executable, "-c", MEMORY_SCRIPT, FILTER, str(PLUGIN),
                               str(limit_mb)], capture_output=True, text=True, timeout=300,
                              cwd=tmp_path)
        return done.returncode, done.stdout.strip(), done.stderr.strip()

    status, out, err = child(-1)
    assert status == 0 and out.endswith("success 0 | uv"), (status, out, err[-500:])
    need = int(out.split()[1])
    results = []
    for fraction in [0.02, 0.1, 0.2, 0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.7, 0.8, 0.9, 1.0,
                     1.2]:
        limit = int(need * fraction)
        status, out, err = child(limit)
        results.append((limit, status, out, err))
        print(f"{limit} MB: status {status}: {out} {err[-300:]}")
    problems = []
    for limit, status, out, err in results:
        if status != 0:
            problems.append(f"{limit} MB: the Python process died (status {status}): {err[-200:]}")
        elif " refused: " not in f" {out}" and not out.endswith("success 0 | uv"):
            problems.append(f"{limit} MB: {out}")
        elif out.startswith("refused: ") and not ("memory" in out.lower()
                                                  and out.endswith("| no uv")):
            problems.append(f"{limit} MB: {out}")
    assert not problems, "\n".join(problems)
    assert any(out.startswith("refused: ") for _, _, out, _ in results), "no limit failed"
    assert any(out.startswith("success") for _, _, out, _ in results), "no limit succeeded"
