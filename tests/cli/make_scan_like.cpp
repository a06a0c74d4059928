// Writes the suite's scan-like mesh (scan_like_mesh.h) made from a clean closed mesh:
//   sdp_make_scan_like IN OUT.off [sigma]
// Used by the meshlabserver case of the atlas on a scan (tests/meshlab).
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "io/mesh_io.h"
#include "scan_like_mesh.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: sdp_make_scan_like IN OUT.off [sigma]\n");
    return 2;
  }
  try {
    sdp::io::MeshData mesh = sdp::io::readMesh(argv[1]);
    sdp::test::ScanLikeOptions options;
    if (argc > 3) options.sigma = std::atof(argv[3]);
    sdp::test::makeScanLike(mesh.V, mesh.F, options);
    if (!sdp::test::writeOff(argv[2], mesh.V, mesh.F)) {
      std::fprintf(stderr, "%s: cannot write\n", argv[2]);
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
