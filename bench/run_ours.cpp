// Runs the project's parameterization on a (optionally subdivided) mesh for the benchmark.
//   usage: sdp_bench MESH [SUBDIVISIONS] [straightest_param options: --weights W --boundary B
//          --stretch-iterations K --source-rule farthest|centroid]
//          sdp_bench MESH SUBDIVISIONS --write-off OUT.off   (only writes the subdivided mesh,
//          so peers in other processes run on exactly the same mesh)
// Prints the report JSON with the peak memory of the run added: peak_rss_mb (whole process)
// and extra_mb (peak during parameterize minus the resident size just before it).
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include "core/parameterize.h"
#include "io/mesh_io.h"
#include "midpoint_subdivision.h"
#include "peak_memory.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: sdp_bench MESH [SUBDIVISIONS] [--weights W] [--boundary B] "
                 "[--stretch-iterations K] [--source-rule R]\n";
    return 2;
  }
  try {
    sdp::io::MeshData data = sdp::io::readMesh(argv[1]);
    int arg = 2;
    int subdivisions = 0;
    if (argc > 2 && argv[2][0] != '-') subdivisions = std::stoi(argv[arg++]);
    sdp::Options options;
    std::string write_off;
    for (; arg + 1 < argc; arg += 2) {
      const std::string key = argv[arg], value = argv[arg + 1];
      if (key == "--weights")
        options.weights = sdp::parseWeightScheme(value).value();
      else if (key == "--boundary")
        options.boundary = sdp::parseBoundaryShape(value).value();
      else if (key == "--stretch-iterations")
        options.stretch_iterations = std::stoi(value);
      else if (key == "--source-rule")
        options.source_rule = sdp::parseSourceRule(value).value();
      else if (key == "--write-off")
        write_off = value;
      else if (key == "--free-boundary")
        options.free_boundary = value != "0";
      else if (key == "--stretch-exponent")
        options.stretch_exponent = std::stod(value);
      else
        throw std::runtime_error("unknown option " + key);
    }
    for (int k = 0; k < subdivisions; ++k) sdp::bench::subdivideMidpoint(data.V, data.F);
    if (!write_off.empty()) {
      std::ofstream out(write_off);
      out.precision(17);
      out << "OFF\n" << data.V.rows() << " " << data.F.rows() << " 0\n";
      for (int v = 0; v < data.V.rows(); ++v)
        out << data.V(v, 0) << " " << data.V(v, 1) << " " << data.V(v, 2) << "\n";
      for (int f = 0; f < data.F.rows(); ++f)
        out << "3 " << data.F(f, 0) << " " << data.F(f, 1) << " " << data.F(f, 2) << "\n";
      return out ? 0 : 1;
    }
    const double before = sdp::bench::currentRssMegabytes();
    sdp::bench::resetPeakRss();
    const sdp::Result result = sdp::parameterize(data.V, data.F, options);
    const double peak = sdp::bench::peakRssMegabytes();
    std::string json = result.report.toJson();
    char extra[160];
    std::snprintf(extra, sizeof extra, "  \"peak_rss_mb\": %.1f,\n  \"extra_mb\": %.1f,\n", peak,
                  peak - before);
    json.insert(2, extra);
    std::cout << json;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "sdp_bench: " << e.what() << "\n";
    return 1;
  }
}
