// libFuzzer target over the whole pipeline a user's file goes through: bytes -> mesh reader ->
// parameterize -> verification. Any crash, sanitizer report, uncaught exception other than the
// one-line ParameterizationError, multi-line reason, or a returned map with a folded face is a
// finding.
//
// Input layout: byte 0 picks the format (off, obj, ply, stl), byte 1 the weights, byte 2 the
// boundary, byte 3 the refinement steps (0-2); the rest is the file. With bit 7 of byte 3 set, the
// file goes through the atlas instead (byte 1 picks a small texture size, byte 2 the gutter, bit 6
// refines the charts), and a stored atlas with a flipped face (faces wound against their
// neighbours measured turned over, as charted), a face without a chart, a UV outside [0,1]^2,
// pixels covered twice or a broken gutter is a finding.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/atlas/atlas.h"
#include "core/atlas/measure.h"
#include "core/common/connectivity.h"
#include "core/parameterize.h"
#include "io/mesh_io.h"

namespace {

[[noreturn]] void finding(const char* what) {
  std::fprintf(stderr, "fuzz finding: %s\n", what);
  std::abort();
}

double uvArea(const sdp::UVs& uv, const sdp::Triangles& F, int f) {
  const auto a = uv.row(F(f, 0)), b = uv.row(F(f, 1)), c = uv.row(F(f, 2));
  return 0.5 * ((b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 4) return 0;
  static const char* const kFormats[] = {"off", "obj", "ply", "stl"};
  const std::string format = kFormats[data[0] % 4];
  sdp::Options options;
  options.weights = static_cast<sdp::WeightScheme>(data[1] % sdp::kWeightSchemeCount);
  options.boundary = static_cast<sdp::BoundaryShape>(data[2] % sdp::kBoundaryShapeCount);
  options.stretch_iterations = data[3] % 3;
  const std::string bytes(reinterpret_cast<const char*>(data + 4), size - 4);

  sdp::io::MeshData mesh;
  try {
    mesh = sdp::io::readMeshFromMemory(bytes, format);
  } catch (const sdp::ParameterizationError& e) {
    if (std::string(e.what()).find('\n') != std::string::npos) finding("multi-line reader reason");
    return 0;
  }
  if (mesh.F.rows() > 4000 || mesh.V.rows() > 4000) return 0;  // keep executions fast
  // The connectivity step reports any mesh: its counts must hang together.
  const sdp::Connectivity c = sdp::analyzeConnectivity(mesh.F, static_cast<int>(mesh.V.rows()));
  for (size_t h = 0; h < c.twin.size(); ++h)
    if (c.twin[h] >= 0 && c.twin[c.twin[h]] != static_cast<int>(h)) finding("twin not mutual");
  for (int component : c.component)
    if (component < 0 || component >= c.components) finding("face outside the components");
  if (c.boundary_loops > c.boundary_edges || c.faces != mesh.F.rows())
    finding("inconsistent connectivity counts");
  if (data[3] & 0x80) {
    if (mesh.F.rows() > 800) return 0;  // an atlas does more work per face
    sdp::atlas::AtlasOptions atlas;
    atlas.texture_size = 64 << (data[1] % 3);
    atlas.gutter = data[2] % 4;
    // The charts' refinement (bit 6) is the costly part: most inputs flatten linearly, so the
    // suite's fixed number of inputs stays within minutes.
    atlas.chart.stretch_iterations = (data[3] & 0x40) ? 1 : 0;
    try {
      const sdp::atlas::AtlasResult r = sdp::atlas::makeAtlas(mesh.V, mesh.F, atlas);
      const sdp::Layout& layout = r.layout;
      if (r.report.flipped_faces != 0) finding("atlas reporting flipped faces");
      if (layout.faceCount() != mesh.F.rows() ||
          layout.chart.size() != static_cast<size_t>(mesh.F.rows()))
        finding("atlas layout of the wrong size");
      if (!layout.uv.allFinite() || layout.uv.minCoeff() < 0 || layout.uv.maxCoeff() > 1)
        finding("atlas UV not finite or outside the unit square");
      for (int c : layout.chart)
        if (c < 0) finding("atlas face without a chart");
      // Faces wound against their neighbours are measured as the atlas charted them: turned
      // over, corners 1 and 2 swapped in the mesh and the layout alike.
      sdp::Triangles turned = mesh.F;
      sdp::Layout measured = layout;
      const std::vector<char> turn = sdp::coherentOrientation(
          mesh.F, sdp::analyzeConnectivity(mesh.F, static_cast<int>(mesh.V.rows())));
      int turned_faces = 0;
      for (Eigen::Index f = 0; f < turned.rows(); ++f)
        if (turn[f]) {
          std::swap(turned(f, 1), turned(f, 2));
          std::swap(measured.face_uv(f, 1), measured.face_uv(f, 2));
          ++turned_faces;
        }
      if (turned_faces != r.report.faces_against_chart) finding("atlas turned-face count");
      const sdp::atlas::AtlasMeasures m =
          sdp::atlas::measureAtlas(mesh.V, turned, measured, atlas.texture_size, atlas.gutter);
      if (m.flipped_faces != 0 || m.mirrored_charts != 0) finding("atlas flipped or mirrored");
      if (m.overlapping_pixels != 0 || m.gutter_violations != 0)
        finding("atlas pixels covered twice or in a gutter");
    } catch (const sdp::ParameterizationError& e) {
      const std::string reason = e.what();
      if (reason.empty() || reason.find('\n') != std::string::npos) finding("bad atlas reason");
    }
    return 0;
  }
  try {
    const sdp::Result result = sdp::parameterize(mesh.V, mesh.F, options);
    if (result.report.flipped_faces != 0) finding("returned a map reporting flipped faces");
    if (result.layout.uv.rows() != mesh.V.rows()) finding("uv rows differ from vertex count");
    if (!result.layout.uv.allFinite()) finding("non-finite texture coordinate");
    for (int f = 0; f < mesh.F.rows(); ++f)
      if (!(uvArea(result.layout.uv, mesh.F, f) > 0))
        finding("returned a folded or degenerate face");
  } catch (const sdp::ParameterizationError& e) {
    const std::string reason = e.what();
    if (reason.empty() || reason.find('\n') != std::string::npos) finding("bad reason text");
  }
  return 0;
}
