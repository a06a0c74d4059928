// The core run on a vcg mesh, in the mesh's numbering: picks the patch (all live faces or the
// selected ones), maps the source vertex from the mesh's numbering to the core's and the report's
// back, and leaves the mesh untouched. Plain C++ on the vcg mesh type: no Qt, no MeshLab.
#pragma once

#include <string>
#include <vector>

#include "core/atlas/atlas.h"
#include "core/parameterize.h"
#include "vcg_adapters/patch_adapter.h"

namespace sdp::vcg_adapter {

struct MeshRun {
  PatchInput input;
  sdp::Result result;              // its report's source_vertex is a mesh index
  std::vector<std::string> notes;  // remarks for the log (e.g. the selected vertex that was used)
};

// `options` as the core takes them, except that `mesh_source_vertex` (-1: automatic) is a mesh
// vertex index; a single selected vertex wins over it (docs/method.md §6). Throws
// sdp::ParameterizationError with the user-facing reason.
template <class MeshType>
MeshRun runOnMesh(const MeshType& mesh, sdp::Options options, bool selected_faces_only,
                  int mesh_source_vertex) {
  MeshRun run;
  run.input = extractPatch(mesh, selected_faces_only);

  const int selected = singleSelectedVertex(mesh);
  if (selected >= 0) {
    if (run.input.coreVertexOf(selected) >= 0) {
      mesh_source_vertex = selected;
      run.notes.push_back("source vertex " + std::to_string(selected) +
                          " taken from the selection");
    } else {
      run.notes.push_back("the selected vertex " + std::to_string(selected) +
                          " is not part of the patch; ignored");
    }
  }
  options.source_vertex = -1;
  if (mesh_source_vertex >= 0) {
    options.source_vertex = run.input.coreVertexOf(mesh_source_vertex);
    if (options.source_vertex < 0) {
      throw sdp::ParameterizationError("source vertex " + std::to_string(mesh_source_vertex) +
                                       " is not a vertex of the patch");
    }
  }

  run.result = sdp::parameterize(run.input.positions, run.input.triangles, options);
  run.result.report.source_vertex = run.input.meshVertexOf(run.result.report.source_vertex);
  return run;
}

struct AtlasRun {
  PatchInput input;
  sdp::atlas::AtlasResult result;
};

// The atlas of all live faces (or the selected ones) of a vcg mesh; the mesh is not touched.
template <class MeshType>
AtlasRun atlasOnMesh(const MeshType& mesh, const sdp::atlas::AtlasOptions& options,
                     bool selected_faces_only) {
  AtlasRun run;
  run.input = extractPatch(mesh, selected_faces_only);
  run.result = sdp::atlas::makeAtlas(run.input.positions, run.input.triangles, options);
  return run;
}

}  // namespace sdp::vcg_adapter
