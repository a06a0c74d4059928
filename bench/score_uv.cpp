// Scores per-vertex texture coordinates made by another tool with the project's metric code.
//   usage: sdp_score MESH UV.txt   (UV.txt: one "u v" line per mesh vertex, in mesh order)
// Prints {"vertices", "l2_stretch", "linf_stretch", "flipped_faces"} as JSON.
#include <cstdio>
#include <fstream>
#include <iostream>

#include "core/parameterize.h"
#include "io/mesh_io.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: sdp_score MESH UV.txt\n";
    return 2;
  }
  try {
    const sdp::io::MeshData data = sdp::io::readMesh(argv[1]);
    std::ifstream in(argv[2]);
    sdp::UVs uv(data.V.rows(), 2);
    for (int v = 0; v < uv.rows(); ++v)
      if (!(in >> uv(v, 0) >> uv(v, 1))) throw std::runtime_error("too few UV lines");
    const sdp::UVMeasures m = sdp::measureUVs(data.V, data.F, uv);
    std::printf(
        "{\"vertices\": %d, \"l2_stretch\": %.9g, \"linf_stretch\": %.9g, \"flipped_faces\": %d}\n",
        static_cast<int>(data.V.rows()), m.l2_stretch, m.linf_stretch, m.flipped_faces);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "sdp_score: " << e.what() << "\n";
    return 1;
  }
}
