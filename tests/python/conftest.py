"""pymeshlab 2025.7 with our 2025.07 plugin loaded, and the shared meshes.

Environment (set by ctest, see tests/meshlab/CMakeLists.txt):
  SDP_PLUGIN_2025      the built plugin (default: <repo>/build/plugins/meshlab-2025.07/...)
  SDP_PLUGIN           the plugin for the pymeshlab running the tests, when it is an older one
  SDP_SHARED_DIR       optional folder with extra meshes in meshes/{disk,invalid} (default:
                       <repo>/../shared); the meshes of resources/meshes are always used
  SDP_REPORT_DIR       where the peer comparison table goes (default: <repo>/build/reports)
"""
import os
import pathlib

import numpy as np
import pytest

FILTER = "compute_texcoord_parametrization_straightest_distances"
REPO = pathlib.Path(__file__).resolve().parents[2]
SHARED = pathlib.Path(os.environ.get("SDP_SHARED_DIR", REPO.parent / "shared"))
BUNDLED = REPO / "resources" / "meshes"
# SDP_PLUGIN: the plugin built for this pymeshlab (an older release's); else the 2025.07 one.
PLUGIN = pathlib.Path(os.environ.get("SDP_PLUGIN") or os.environ.get(
    "SDP_PLUGIN_2025", REPO / "build/plugins/meshlab-2025.07/libfilter_straightest_param.so"))
REPORT_DIR = pathlib.Path(os.environ.get("SDP_REPORT_DIR", REPO / "build/reports"))

# Upstream PyMeshLab issue #399: after a filter raises, pymeshlab's loggers point into the log of
# the MeshSet that ran it until a filter succeeds, so the next load into a new MeshSet writes into
# freed memory (seen here as SIGSEGV, or std::bad_alloc from load_new_mesh). The tests refuse on
# purpose, one case after another, so they call the filter as the pip package's bound method does
# (python/pymeshlab_straightest): refused MeshSets are kept alive and a trivial filter succeeds.
_refused_mesh_sets = []


def run_guarded(ms, filter_name=FILTER, **parameters):
    """Our filter (the patch filter unless named) on `ms`, with the #399 guard."""
    import pymeshlab
    try:
        report = getattr(ms, filter_name)(**parameters)
    except BaseException:
        _refused_mesh_sets.append(ms)
        scratch = pymeshlab.MeshSet()
        scratch.add_mesh(pymeshlab.Mesh(
            vertex_matrix=np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]),
            face_matrix=np.array([[0, 1, 2]], dtype=np.int32)))
        scratch.apply_filter("set_selection_none")
        raise
    _refused_mesh_sets.clear()
    return report



def test_meshes(folder):
    """The bundled meshes of a folder plus the extra set's others, each name once, by name."""
    found = {}
    for root in (BUNDLED, SHARED / "meshes"):
        for path in sorted((root / folder).glob("*.off")):
            found.setdefault(path.name, path)
    return [found[name] for name in sorted(found)]


DISK_MESHES = test_meshes("disk")
INVALID_MESHES = test_meshes("invalid")
# Labels exactly as docs/method.md section 6 (pymeshlab takes enum values by label).
WEIGHTS = ["Straightest distances (cutting planes)", "LTD straightest geodesics",
           "Floater shape-preserving", "Mean value", "Uniform"]
BOUNDARIES = {"measured": "Measured (straightest distances)", "circle": "Circle",
              "square": "Square"}


@pytest.fixture(scope="session")
def ml():
    """The pymeshlab module with our filter loaded and bound as a MeshSet method."""
    if not PLUGIN.exists():
        pytest.skip(f"plugin {PLUGIN} not built")
    import pymeshlab

    if FILTER not in pymeshlab.filter_list():
        pymeshlab.load_plugin(str(PLUGIN))
    # pymeshlab binds MeshSet methods only for the plugins present at import time.
    if not hasattr(pymeshlab.MeshSet, FILTER):
        setattr(pymeshlab.MeshSet, FILTER, pymeshlab.bind_function(FILTER))
    return pymeshlab
