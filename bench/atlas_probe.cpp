// Development probe: the atlas of one mesh, its measures as stored (not part of the product).
//   sdp_atlas_probe MESH [max_chart_stretch [texture_size [OUT.obj|- [work_factor]]]]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/atlas/atlas.h"
#include "core/atlas/measure.h"
#include "io/mesh_io.h"

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  const auto mesh = sdp::io::readMesh(argv[1]);
  sdp::atlas::AtlasOptions o;
  if (argc > 2) o.max_chart_stretch = std::atof(argv[2]);
  if (argc > 3) o.texture_size = std::atoi(argv[3]);
  // The charts' refinement work factor (the CLI's --time-budget; 0: no limit).
  if (argc > 5) {
    o.chart.refine_work_factor = std::atof(argv[5]);
    if (o.chart.refine_work_factor == 0) o.chart.refine_min_work = 0;
  }
  const auto start = std::chrono::steady_clock::now();
  auto r = sdp::atlas::makeAtlas(mesh.V, mesh.F, o);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto m = sdp::atlas::measureAtlas(mesh.V, mesh.F, r.layout, o.texture_size, o.gutter);
  std::printf(
      "%s charts %d (by uv %d) split %d L2 %.4f Linf %.2f seam %.2f eff %.3f flips %d mirrored %d "
      "overlap %lld gutter %lld outside %d  %.2fs\n",
      argv[1], r.report.charts, m.charts, r.report.charts_split, m.l2, m.linf, m.seam, m.efficiency,
      m.flipped_faces, m.mirrored_charts, m.overlapping_pixels, m.gutter_violations,
      m.outside_faces, s);
  for (auto& [k, v] : r.report.stage_seconds) std::printf("  %s %.2f", k.c_str(), v);
  std::printf("\n");
  if (argc > 4 && std::string(argv[4]) != "-")
    sdp::io::writeObjWithTexture(argv[4], mesh.V, mesh.F, r.layout, "checker.png");
}
