"""The straightest-distance parameterization filters for pymeshlab 2025.7.post1, 2023.12.post3 and
2022.2.post4 (the package carries a plugin built for each and loads the one for the pymeshlab
installed; any other release is refused at import with the reason).

    import pymeshlab
    import pymeshlab_straightest  # loads the plugin, binds the MeshSet method

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh("patch.off")
    report = ms.compute_texcoord_parametrization_straightest_distances()

Importing loads the plugin for the installed pymeshlab (MeshLab 2025.07, 2023.12 or 2022.02,
double precision) into pymeshlab and binds ``MeshSet.compute_texcoord_parametrization_straightest_distances``, which
takes the filter's parameters as keywords (``weights``, ``boundary``, ``sourcevertex``,
``stretchiterations``, ``selectedonly``, ``texturename``, ``checkers``, ``texturesize``) and
returns the report dict (``l2_stretch``, ``linf_stretch``, ``flipped_faces``, ``fallbacks``,
``source_vertex``, ``seconds``). A mesh the filter refuses raises
``pymeshlab.PyMeshLabException`` whose message ends with the one-line reason; the mesh is left
as it was.

It also binds ``MeshSet.compute_texcoord_parametrization_straightest_distances_atlas``, the atlas
of any mesh (closed, any genus, many pieces): keywords ``texturesize``, ``gutter``,
``chartstretch``, ``stretchiterations``, ``refinementwork``, ``selectedonly``, ``texturename``,
``checkers``; it returns ``charts``, ``seam``, ``packing_efficiency``, ``l2_stretch``,
``linf_stretch``, ``flipped_faces``, ``overlapping_charts``, ``seconds``,
``faces_against_chart`` (faces wound against their neighbours, charted turned over), and the
chart of each face is ``ms.current_mesh().face_custom_scalar_attribute_array("chart")``.

Both dicts also hold ``polygons_as_triangles`` (True when the mesh was read from polygons: it is
then saved as the triangles that carry the map, since MeshLab's polygonal export drops per-wedge
texture coordinates) and ``notes``, a list of sentences saying what those counts mean.

Batches: in pymeshlab 2025.7, a loop that catches a filter's exception and goes on to a new
``MeshSet`` crashes the interpreter at the next load (upstream PyMeshLab issue #399). The cause:
when a filter raises, pymeshlab leaves its process-wide progress logger, and for a verbose
``MeshSet`` the plugin's logger too, pointing into the log of the ``MeshSet`` that ran it; only
a filter that succeeds resets them, so the next importer writes into a destroyed log. The bound
method here repairs that state whenever our filter raises: it runs one trivial filter on a
throw-away one-triangle mesh (which resets the process-wide logger) and keeps the failed
``MeshSet`` objects alive until our filter next succeeds (which resets the plugin's). So a loop
like this is safe, whatever mix of good and bad meshes it meets::

    for path in paths:
        ms = pymeshlab.MeshSet()
        ms.load_new_mesh(path)
        try:
            report = ms.compute_texcoord_parametrization_straightest_distances()
        except pymeshlab.PyMeshLabException as error:
            print(path, "refused:", str(error).splitlines()[-1])

Keep such a loop in one thread (pymeshlab's logger is process-wide), and start a new
``MeshSet`` after a refusal rather than filtering the refused one again.
"""
import os
from importlib.metadata import version as _installed_version

import numpy as np
import pymeshlab

from ._version import VERSION as __version__  # noqa: F401

FILTER_NAME = "compute_texcoord_parametrization_straightest_distances"
ATLAS_FILTER_NAME = FILTER_NAME + "_atlas"
HERE = os.path.dirname(os.path.abspath(__file__))


def _plugin_for_installed_pymeshlab():
    """The plugin built for the pymeshlab installed; ImportError naming the releases served."""
    try:
        from ._plugins import PLUGINS
    except ImportError:
        raise ImportError("pymeshlab_straightest: the package has no plugins (it was built from "
                          "python/ alone; scripts/make-wheel.sh makes the wheel)") from None
    installed = _installed_version("pymeshlab")
    if installed not in PLUGINS:
        raise ImportError(
            "pymeshlab_straightest: pymeshlab %s is not served: MeshLab loads only a plugin built "
            "for its own version, and this package has plugins for pymeshlab %s; "
            "pip install pymeshlab==%s" % (installed, ", ".join(sorted(PLUGINS)), max(PLUGINS)))
    return os.path.join(HERE, PLUGINS[installed][1])


PLUGIN_PATH = _plugin_for_installed_pymeshlab()

# MeshSets whose run of our filter raised: pymeshlab may still hold pointers into their logs
# until our filter next succeeds, so they must outlive the caller's references.
_refused_mesh_sets = []


def _reset_pymeshlab_logging():
    """A trivial filter that succeeds: pymeshlab resets its process-wide logger at its end."""
    scratch = pymeshlab.MeshSet()
    scratch.add_mesh(pymeshlab.Mesh(
        vertex_matrix=np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
        face_matrix=np.array([[0, 1, 2]], dtype=np.int32)))
    scratch.apply_filter("set_selection_none")


def _notes(report):
    """What MeshLab's log says beside the numbers, for the dict's `notes` (pymeshlab hands only
    numbers on from a filter, so the plugin gives counts and they are worded here)."""
    notes = []
    if report.get("polygons_as_triangles"):
        notes.append("the mesh's polygons are saved as the triangles that carry the map: "
                      "MeshLab's polygonal export (save_polygonal=True, the export dialog's "
                      "Polygonal box) drops per-wedge texture coordinates, so it is turned off "
                      "for this mesh")
    if report.get("faces_against_chart"):
        notes.append("%d faces are wound against their neighbours: charted as the surface runs, "
                     "their texture triangles run clockwise; "
                     "ms.meshing_re_orient_faces_coherently() fixes the winding"
                     % report["faces_against_chart"])
    return notes


def _bound(filter_name, doc):
    def run(self, **parameters):
        try:
            report = self.apply_filter(filter_name, **parameters)
        except BaseException:
            _refused_mesh_sets.append(self)
            try:
                _reset_pymeshlab_logging()
            except Exception:  # the caller must see the filter's own error, not this one
                pass
            raise
        # Success reset both of pymeshlab's loggers: the refused MeshSets may go.
        _refused_mesh_sets.clear()
        report["notes"] = _notes(report)
        return report
    run.__name__ = filter_name
    run.__doc__ = doc
    return run


compute_texcoord_parametrization_straightest_distances = _bound(
    FILTER_NAME,
    "Parametrization: Straightest Distances (see help(pymeshlab_straightest)). Keyword "
    "parameters as in MeshLab's dialog; returns the report dict.")
compute_texcoord_parametrization_straightest_distances_atlas = _bound(
    ATLAS_FILTER_NAME,
    "Parametrization: Straightest Distances Atlas (see help(pymeshlab_straightest)). Keyword "
    "parameters as in MeshLab's dialog; returns the report dict.")


def _load():
    if not os.path.isfile(PLUGIN_PATH):
        raise ImportError("pymeshlab_straightest: the plugin %s is missing from the package"
                          % PLUGIN_PATH)
    if FILTER_NAME not in pymeshlab.filter_list():
        pymeshlab.load_plugin(PLUGIN_PATH)
    setattr(pymeshlab.MeshSet, FILTER_NAME, compute_texcoord_parametrization_straightest_distances)
    setattr(pymeshlab.MeshSet, ATLAS_FILTER_NAME,
            compute_texcoord_parametrization_straightest_distances_atlas)


_load()
