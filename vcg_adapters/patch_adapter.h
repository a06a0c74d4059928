// vcglib mesh <-> core (docs/architecture.md: MeshLab -> adapter -> core -> adapter -> MeshLab).
// Numbering: vcg indices (mesh.vert, mesh.face, deleted elements included) <-> core indices
// (PatchInput: the patch's vertices and faces in vcg order, deleted and unselected left out).
// Header-only templates on the vcg mesh type, so the same code compiles against the vcglib of
// MeshLab 2020.09 and of 2025.07. No Qt, no MeshLab: the shims add those parts.
//
// extractPatch() and prepareResult() read; applyResult() is the only function that writes, and
// the shims call it only after the core and prepareResult() succeeded, so a failed run leaves
// the mesh exactly as it was.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <vcg/complex/complex.h>

#include "core/parameterize.h"

namespace sdp::vcg_adapter {

// The core's input plus the index maps between the core's compact numbering and the positions
// in the vcg containers (which may hold deleted elements). Core vertices keep the mesh order, so
// on a mesh without deleted or unreferenced vertices both numberings agree.
struct PatchInput {
  sdp::Positions positions;
  sdp::Triangles triangles;
  std::vector<int> mesh_vertex;  // core vertex -> index in mesh.vert
  std::vector<int> core_vertex;  // index in mesh.vert -> core vertex, -1 when not in the patch
  std::vector<int> mesh_face;    // core face -> index in mesh.face

  // -1 when the mesh vertex is not part of the patch (deleted, unreferenced or unselected).
  int coreVertexOf(int mesh_index) const {
    if (mesh_index < 0 || mesh_index >= static_cast<int>(core_vertex.size())) return -1;
    return core_vertex[mesh_index];
  }
  int meshVertexOf(int core_index) const {
    if (core_index < 0 || core_index >= static_cast<int>(mesh_vertex.size())) return -1;
    return mesh_vertex[core_index];
  }
};

// Live (non-deleted) faces, or only the selected ones, and the vertices they use. Coordinates are
// copied as they are: a NaN reaches the core, which rejects it with its own one-line reason.
template <class MeshType>
PatchInput extractPatch(const MeshType& mesh, bool selected_faces_only) {
  PatchInput in;
  const int vertex_count = static_cast<int>(mesh.vert.size());
  const auto* first_vertex = vertex_count > 0 ? &mesh.vert[0] : nullptr;

  std::vector<char> used(vertex_count, 0);
  for (int fi = 0; fi < static_cast<int>(mesh.face.size()); ++fi) {
    const auto& f = mesh.face[fi];
    if (f.IsD() || (selected_faces_only && !f.IsS())) continue;
    bool valid = true;
    for (int k = 0; k < 3; ++k) {
      const auto* v = f.cV(k);
      valid = valid && v != nullptr && !v->IsD();
    }
    if (!valid) continue;  // a face on a deleted vertex is garbage, not geometry
    in.mesh_face.push_back(fi);
    for (int k = 0; k < 3; ++k) used[f.cV(k) - first_vertex] = 1;
  }
  if (in.mesh_face.empty()) {
    throw sdp::ParameterizationError(selected_faces_only ? "no faces are selected"
                                                         : "the mesh has no faces");
  }

  in.core_vertex.assign(vertex_count, -1);
  for (int vi = 0; vi < vertex_count; ++vi) {
    if (!used[vi]) continue;
    in.core_vertex[vi] = static_cast<int>(in.mesh_vertex.size());
    in.mesh_vertex.push_back(vi);
  }

  in.positions.resize(static_cast<Eigen::Index>(in.mesh_vertex.size()), 3);
  for (size_t i = 0; i < in.mesh_vertex.size(); ++i) {
    const auto& p = mesh.vert[in.mesh_vertex[i]].cP();
    for (int c = 0; c < 3; ++c) in.positions(i, c) = static_cast<double>(p[c]);
  }
  in.triangles.resize(static_cast<Eigen::Index>(in.mesh_face.size()), 3);
  for (size_t i = 0; i < in.mesh_face.size(); ++i) {
    const auto& f = mesh.face[in.mesh_face[i]];
    for (int k = 0; k < 3; ++k) {
      in.triangles(i, k) = in.core_vertex[f.cV(k) - first_vertex];
    }
  }
  return in;
}

// The mesh index of the only selected live vertex, or -1 when none or several are selected
// (a single selected vertex picks the source S of the measured boundary in MeshLab).
template <class MeshType>
int singleSelectedVertex(const MeshType& mesh) {
  int found = -1;
  for (int vi = 0; vi < static_cast<int>(mesh.vert.size()); ++vi) {
    const auto& v = mesh.vert[vi];
    if (v.IsD() || !v.IsS()) continue;
    if (found != -1) return -1;
    found = vi;
  }
  return found;
}

struct WriteOptions {
  bool wedge_texcoords = true;    // per-wedge UVs (texture index below)
  bool vertex_texcoords = false;  // also per-vertex UVs
  bool face_quality = true;       // per-face quality = normalized L2 stretch of the stored face
  short texture_index = 0;
};

namespace detail {

// Optional (ocf) components are switched on; meshes with static components already have them.
template <class Container>
auto enableWedgeTexCoord(Container& c, int) -> decltype(c.EnableWedgeTexCoord(), void()) {
  if (!c.IsWedgeTexCoordEnabled()) c.EnableWedgeTexCoord();
}
template <class Container>
void enableWedgeTexCoord(Container&, long) {}

template <class Container>
auto enableFaceQuality(Container& c, int) -> decltype(c.EnableQuality(), void()) {
  if (!c.IsQualityEnabled()) c.EnableQuality();
}
template <class Container>
void enableFaceQuality(Container&, long) {}

template <class Container>
auto enableVertexTexCoord(Container& c, int) -> decltype(c.EnableTexCoord(), void()) {
  if (!c.IsTexCoordEnabled()) c.EnableTexCoord();
}
template <class Container>
void enableVertexTexCoord(Container&, long) {}

}  // namespace detail

// Switches on the components applyResult() fills. (MeshLab shims call MeshModel::updateDataMask
// first, which does the same and also keeps MeshModel's bookkeeping right.)
template <class MeshType>
void enableResultComponents(MeshType& mesh, const WriteOptions& options) {
  if (options.wedge_texcoords) detail::enableWedgeTexCoord(mesh.face, 0);
  if (options.face_quality) detail::enableFaceQuality(mesh.face, 0);
  if (options.vertex_texcoords) detail::enableVertexTexCoord(mesh.vert, 0);
}

// MeshLab stores texture coordinates in single precision even when its scalar is double.
template <class MeshType>
using TexScalarOf = typename MeshType::FaceType::TexCoordType::ScalarType;

// What the core returns for MeshLab: UVs in the unit square, rounded to what MeshLab's float
// texture coordinates and its OBJ exporter's 6 decimals hold, one-to-one as stored.
inline void setMeshLabStorage(sdp::Options& options) {
  options.storage = {true, sdp::UVStorage::FloatAndSixDecimals};
}

// The UVs exactly as the mesh will hold them, and the per-face stretch the faces' quality gets.
// The core measured and certified the map as stored (setMeshLabStorage), so its report already
// speaks of these values.
template <class TexScalar>
struct StoredResult {
  std::vector<TexScalar> u, v;       // per row of the layout's uv
  sdp::Triangles face_uv;            // per patch face and corner: its row (the layout's face_uv)
  std::vector<double> face_stretch;  // per patch face
};

// Computes what applyResult() writes, without touching the mesh. The layout's UVs must already
// be storable: a value the mesh cannot hold exactly would change the map after the core's final
// check, so this conversion, the adapter's own, refuses such a value.
template <class MeshType>
StoredResult<TexScalarOf<MeshType>> prepareLayout(const PatchInput& in, const sdp::Layout& layout,
                                                  const std::vector<double>& face_stretch) {
  using TexScalar = TexScalarOf<MeshType>;
  if (layout.face_uv.rows() != static_cast<Eigen::Index>(in.mesh_face.size()) ||
      face_stretch.size() != in.mesh_face.size() ||
      (layout.face_uv.size() > 0 &&
       (layout.face_uv.minCoeff() < 0 || layout.face_uv.maxCoeff() >= layout.uv.rows()))) {
    throw sdp::ParameterizationError("internal error: the result does not match the patch");
  }
  StoredResult<TexScalar> stored;
  const Eigen::Index n = layout.uv.rows();
  stored.u.resize(n);
  stored.v.resize(n);
  stored.face_uv = layout.face_uv;
  for (Eigen::Index i = 0; i < n; ++i) {
    stored.u[i] = static_cast<TexScalar>(layout.uv(i, 0));
    stored.v[i] = static_cast<TexScalar>(layout.uv(i, 1));
    if (static_cast<double>(stored.u[i]) != layout.uv(i, 0) ||
        static_cast<double>(stored.v[i]) != layout.uv(i, 1)) {
      throw sdp::ParameterizationError(
          "internal error: the texture coordinates were not rounded for MeshLab's storage");
    }
  }
  stored.face_stretch = face_stretch;
  return stored;
}

// Copies the prepared UVs and per-face stretch (quality) into the patch's faces (and vertices).
// Elements outside the patch keep what they had.
template <class MeshType>
void applyResult(MeshType& mesh, const PatchInput& in,
                 const StoredResult<TexScalarOf<MeshType>>& stored,
                 const WriteOptions& options = {}) {
  enableResultComponents(mesh, options);
  if ((options.wedge_texcoords && !vcg::tri::HasPerWedgeTexCoord(mesh)) ||
      (options.face_quality && !vcg::tri::HasPerFaceQuality(mesh)) ||
      (options.vertex_texcoords && !vcg::tri::HasPerVertexTexCoord(mesh))) {
    throw sdp::ParameterizationError("the mesh type cannot store texture coordinates");
  }
  for (size_t i = 0; i < in.mesh_face.size(); ++i) {
    auto& f = mesh.face[in.mesh_face[i]];
    if (options.wedge_texcoords) {
      for (int k = 0; k < 3; ++k) {
        const int row = stored.face_uv(i, k);
        f.WT(k).U() = stored.u[row];
        f.WT(k).V() = stored.v[row];
        f.WT(k).N() = options.texture_index;
      }
    }
    if (options.face_quality) {
      f.Q() = static_cast<typename MeshType::FaceType::QualityType>(stored.face_stretch[i]);
    }
  }
  if (options.vertex_texcoords) {
    // A vertex holds one coordinate: on a seam, the one its first corner carries.
    std::vector<int> row_of_vertex(in.mesh_vertex.size(), -1);
    for (Eigen::Index f = stored.face_uv.rows() - 1; f >= 0; --f)
      for (int k = 2; k >= 0; --k) row_of_vertex[in.triangles(f, k)] = stored.face_uv(f, k);
    for (size_t i = 0; i < in.mesh_vertex.size(); ++i) {
      if (row_of_vertex[i] < 0) continue;
      auto& t = mesh.vert[in.mesh_vertex[i]].T();
      t.U() = stored.u[row_of_vertex[i]];
      t.V() = stored.v[row_of_vertex[i]];
      t.N() = options.texture_index;
    }
  }
}

// The atlas's chart per face as the per-face attribute "chart" (the mesh's scalar type, which
// pymeshlab reads as face_scalar_attribute_array("chart")); faces outside the input keep theirs
// (-1 when the attribute is new).
template <class MeshType>
void applyCharts(MeshType& mesh, const PatchInput& in, const std::vector<int>& chart) {
  using Scalar = typename MeshType::ScalarType;
  const bool existed = vcg::tri::HasPerFaceAttribute(mesh, "chart");
  auto handle = vcg::tri::Allocator<MeshType>::template GetPerFaceAttribute<Scalar>(mesh, "chart");
  if (!existed)
    for (size_t f = 0; f < mesh.face.size(); ++f) handle[f] = Scalar(-1);
  for (size_t i = 0; i < in.mesh_face.size() && i < chart.size(); ++i)
    handle[in.mesh_face[i]] = static_cast<Scalar>(chart[i]);
}

}  // namespace sdp::vcg_adapter
