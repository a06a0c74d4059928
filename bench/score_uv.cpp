// Scores per-vertex texture coordinates made by another tool with the project's metric code.
//   usage: sdp_score MESH UV.txt   (UV.txt: one "u v" line per mesh vertex, in mesh order)
// Prints {"vertices", "l2_stretch", "linf_stretch", "flipped_faces"} as JSON.
#include <cstdio>
#include <fstream>
#include <iostream>

#include "core/metrics.h"
#include "core/patch.h"
#include "mesh_io.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: sdp_score MESH UV.txt\n";
    return 2;
  }
  try {
    const sdp::io::MeshData data = sdp::io::readMesh(argv[1]);
    std::ifstream in(argv[2]);
    std::vector<Eigen::Vector2d> uv(data.V.rows());
    for (auto& p : uv)
      if (!(in >> p.x() >> p.y())) throw std::runtime_error("too few UV lines");
    const sdp::Patch patch = sdp::buildPatch(data.V, data.F);
    std::vector<Eigen::Vector2d> local(patch.vertexCount());
    for (int v = 0; v < patch.vertexCount(); ++v) local[v] = uv[patch.input_vertex[v]];
    const sdp::StretchMetrics m = sdp::stretchMetrics(patch, local);
    std::printf(
        "{\"vertices\": %d, \"l2_stretch\": %.9g, \"linf_stretch\": %.9g, \"flipped_faces\": %d}\n",
        patch.vertexCount(), m.l2, m.linf, m.flipped_faces);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "sdp_score: " << e.what() << "\n";
    return 1;
  }
}
