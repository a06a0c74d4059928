// libFuzzer target over the whole pipeline a user's file goes through: bytes -> mesh reader ->
// parameterize -> verification. Any crash, sanitizer report, uncaught exception other than the
// one-line ParameterizationError, multi-line reason, or a returned map with a folded face is a
// finding.
//
// Input layout: byte 0 picks the format (off, obj, ply), byte 1 the weights, byte 2 the boundary,
// byte 3 the refinement steps (0-2); the rest is the file.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/connectivity.h"
#include "core/parameterize.h"
#include "mesh_io.h"

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
  static const char* const kFormats[] = {"off", "obj", "ply"};
  const std::string format = kFormats[data[0] % 3];
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
