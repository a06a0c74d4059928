// Scores an atlas as another tool wrote it (or as we did) with the project's own measures
// (core/atlas/measure.h), from the file alone: its per-corner texture coordinates.
//   usage: sdp_atlas_score RESULT.obj|RESULT.ply TEXTURE_SIZE GUTTER [--weld]
// RESULT is read by the io/ library (OBJ `vt` with `f v/vt`, or PLY texcoord lists; polygons
// fan-triangulated). --weld merges
// vertices at identical positions first, for tools that split vertices along their seams (else a
// seam would look like the mesh's own boundary and go uncounted).
// Prints one JSON object: faces, charts, seam, mirrored_charts, flipped_faces,
// overlapping_pixels, gutter_violations, outside_faces, uncharted_faces, efficiency, l2, linf,
// winding_turned_faces (faces read turned over: below).
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "core/atlas/measure.h"
#include "core/common/connectivity.h"
#include "io/mesh_io.h"

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: sdp_atlas_score RESULT.obj TEXTURE_SIZE GUTTER [--weld]\n");
    return 2;
  }
  try {
    const sdp::io::MeshData m = sdp::io::readMesh(argv[1]);
    const int texture_size = std::atoi(argv[2]);
    const int gutter = std::atoi(argv[3]);
    const bool weld = argc > 4 && std::string(argv[4]) == "--weld";
    const int vertex_count = static_cast<int>(m.V.rows());
    std::vector<int> welded(vertex_count);
    std::map<std::array<double, 3>, int> first_at;
    int kept = 0;
    for (int v = 0; v < vertex_count; ++v) {
      if (!weld) {
        welded[v] = kept++;
        continue;
      }
      const auto [at, inserted] =
          first_at.emplace(std::array<double, 3>{m.V(v, 0), m.V(v, 1), m.V(v, 2)}, kept);
      welded[v] = at->second;
      if (inserted) ++kept;
    }
    sdp::Positions V(kept, 3);
    for (int v = 0; v < vertex_count; ++v) V.row(welded[v]) = m.V.row(v);
    // Faces with a corner the file gives no texture coordinate are left out, and counted.
    // (A file without any has an empty texcoords layout: every face is left out.)
    std::vector<int> textured;
    const bool has_texcoords = m.texcoords.face_uv.rows() == m.F.rows();
    for (int f = 0; has_texcoords && f < m.F.rows(); ++f)
      if ((m.texcoords.face_uv.row(f).array() >= 0).all()) textured.push_back(f);
    const int faces = static_cast<int>(textured.size());
    const int faces_without_uv = static_cast<int>(m.F.rows()) - faces;
    sdp::Triangles F(faces, 3);
    sdp::Layout layout;
    layout.uv = m.texcoords.uv;
    layout.face_uv.resize(faces, 3);
    for (int i = 0; i < faces; ++i)
      for (int k = 0; k < 3; ++k) {
        F(i, k) = welded[m.F(textured[i], k)];
        layout.face_uv(i, k) = m.texcoords.face_uv(textured[i], k);
      }
    sdp::atlas::AtlasMeasures a = sdp::atlas::measureAtlas(V, F, layout, texture_size, gutter);
    // A mesh whose faces are not wound alike (some against their neighbours) has two fair
    // readings of a texture triangle's winding: against the file's order of corners, or against
    // the surface's coherent orientation, which an atlas that charts across those edges follows.
    // Each tool is judged by the reading it followed: the one with fewer flipped faces and
    // mirrored charts.
    int turned_faces = 0;
    const sdp::Connectivity connectivity = sdp::analyzeConnectivity(F, kept);
    if (connectivity.inconsistent_edges > 0) {
      const std::vector<char> turn = sdp::coherentOrientation(F, connectivity);
      sdp::Triangles turned_F = F;
      sdp::Layout turned_layout = layout;
      int turned = 0;
      for (int f = 0; f < faces; ++f)
        if (turn[f]) {
          std::swap(turned_F(f, 1), turned_F(f, 2));
          std::swap(turned_layout.face_uv(f, 1), turned_layout.face_uv(f, 2));
          ++turned;
        }
      const sdp::atlas::AtlasMeasures coherent =
          sdp::atlas::measureAtlas(V, turned_F, turned_layout, texture_size, gutter);
      if (coherent.flipped_faces + coherent.mirrored_charts < a.flipped_faces + a.mirrored_charts) {
        a = coherent;
        turned_faces = turned;
      }
    }
    // Stretch is unbounded where a UV triangle has no area: JSON has no infinity, so null.
    auto number = [](double x) {
      char text[32];
      if (!std::isfinite(x)) return std::string("null");
      std::snprintf(text, sizeof text, "%.9g", x);
      return std::string(text);
    };
    std::printf(
        "{\"faces\": %d, \"charts\": %d, \"seam\": %s, \"mirrored_charts\": %d, "
        "\"flipped_faces\": %d, \"overlapping_pixels\": %lld, \"gutter_violations\": %lld, "
        "\"outside_faces\": %d, \"uncharted_faces\": %d, \"efficiency\": %s, \"l2\": %s, "
        "\"linf\": %s, \"winding_turned_faces\": %d}\n",
        faces, a.charts, number(a.seam).c_str(), a.mirrored_charts, a.flipped_faces,
        a.overlapping_pixels, a.gutter_violations, a.outside_faces, faces_without_uv,
        number(a.efficiency).c_str(), number(a.l2).c_str(), number(a.linf).c_str(), turned_faces);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sdp_atlas_score: %s\n", e.what());
    return 1;
  }
}
