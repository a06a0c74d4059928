// The CGAL 5.5 peers of the benchmark (Surface_mesh_parameterization with its default solver
// and the arc-length circle border): Tutte, mean value, discrete conformal, discrete authalic.
// Built only for the benchmark; CGAL code is used through its headers, nothing is copied.
// Scores the result with the project's own metric code, so every row of a table is comparable.
//   usage: sdp_cgal_peer MESH METHOD [SUBDIVISIONS]   (METHOD: tutte|mean_value|conformal|authalic)
// Prints one JSON object: method, vertices, seconds (CGAL's parameterize call only), l2, linf,
// flipped_faces, peak_rss_mb.
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/Barycentric_mapping_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Circular_border_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_authalic_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_conformal_map_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Mean_value_coordinates_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>

#include "core/parameterize.h"
#include "io/mesh_io.h"
#include "midpoint_subdivision.h"
#include "peak_memory.h"

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = SurfaceMesh::Vertex_index;
using UVMap = SurfaceMesh::Property_map<VertexIndex, Kernel::Point_2>;
namespace SMP = CGAL::Surface_mesh_parameterization;
using Border = SMP::Circular_border_arc_length_parameterizer_3<SurfaceMesh>;

template <class Parameterizer>
SMP::Error_code run(SurfaceMesh& mesh, UVMap uv) {
  const auto border = CGAL::Polygon_mesh_processing::longest_border(mesh).first;
  return SMP::parameterize(mesh, Parameterizer(), border, uv);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: sdp_cgal_peer MESH tutte|mean_value|conformal|authalic [SUBDIVISIONS]\n";
    return 2;
  }
  try {
    sdp::io::MeshData data = sdp::io::readMesh(argv[1]);
    const int subdivisions = argc > 3 ? std::stoi(argv[3]) : 0;
    for (int k = 0; k < subdivisions; ++k) sdp::bench::subdivideMidpoint(data.V, data.F);
    const std::string method = argv[2];

    SurfaceMesh mesh;
    std::vector<VertexIndex> vertex(data.V.rows());
    for (int v = 0; v < data.V.rows(); ++v)
      vertex[v] = mesh.add_vertex(Kernel::Point_3(data.V(v, 0), data.V(v, 1), data.V(v, 2)));
    for (int f = 0; f < data.F.rows(); ++f)
      mesh.add_face(vertex[data.F(f, 0)], vertex[data.F(f, 1)], vertex[data.F(f, 2)]);
    UVMap uv = mesh.add_property_map<VertexIndex, Kernel::Point_2>("v:uv").first;

    const auto start = std::chrono::steady_clock::now();
    SMP::Error_code status;
    if (method == "tutte")
      status = run<SMP::Barycentric_mapping_parameterizer_3<SurfaceMesh, Border>>(mesh, uv);
    else if (method == "mean_value")
      status = run<SMP::Mean_value_coordinates_parameterizer_3<SurfaceMesh, Border>>(mesh, uv);
    else if (method == "conformal")
      status = run<SMP::Discrete_conformal_map_parameterizer_3<SurfaceMesh, Border>>(mesh, uv);
    else if (method == "authalic")
      status = run<SMP::Discrete_authalic_parameterizer_3<SurfaceMesh, Border>>(mesh, uv);
    else
      throw std::runtime_error("unknown method " + method);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    sdp::UVs scored(data.V.rows(), 2);
    for (int v = 0; v < scored.rows(); ++v) scored.row(v) << uv[vertex[v]].x(), uv[vertex[v]].y();
    const sdp::UVMeasures m = sdp::measureUVs(data.V, data.F, scored);
    std::printf(
        "{\"method\": \"cgal_%s\", \"status\": \"%s\", \"vertices\": %d, \"seconds\": %.6f, "
        "\"l2_stretch\": %.9g, \"linf_stretch\": %.9g, \"flipped_faces\": %d, \"peak_rss_mb\": "
        "%.1f}\n",
        method.c_str(), status == SMP::OK ? "ok" : SMP::get_error_message(status),
        static_cast<int>(data.V.rows()), seconds, m.l2_stretch, m.linf_stretch, m.flipped_faces,
        sdp::bench::peakRssMegabytes());
    return status == SMP::OK ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "sdp_cgal_peer: " << e.what() << "\n";
    return 1;
  }
}
