// Scores an atlas as another tool wrote it (or as we did) with the project's own measures
// (core/atlas/measure.h), from the file alone: per-corner texture coordinates of an OBJ.
//   usage: sdp_atlas_score RESULT.obj TEXTURE_SIZE GUTTER [--weld]
// RESULT.obj holds `v`, `vt` and `f v/vt ...` lines (polygons fan-triangulated). --weld merges
// vertices at identical positions first, for tools that split vertices along their seams (else a
// seam would look like the mesh's own boundary and go uncounted).
// Prints one JSON object: faces, charts, seam, mirrored_charts, flipped_faces,
// overlapping_pixels, gutter_violations, outside_faces, uncharted_faces, efficiency, l2, linf.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/atlas/measure.h"

namespace {

struct TexturedMesh {
  std::vector<double> xyz, uv;
  std::vector<int> face_v, face_vt;  // per triangle corner, 0-based
  int faces_without_uv = 0;
};

int objIndex(const std::string& token, int defined) {
  const long long i = std::stoll(token);
  if (i < 0) return static_cast<int>(defined + i);
  if (i == 0) throw std::runtime_error("index 0 in OBJ");
  return static_cast<int>(i - 1);
}

TexturedMesh readTexturedObj(const char* path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(std::string("cannot open ") + path);
  TexturedMesh m;
  std::string line, word;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    if (!(s >> word)) continue;
    if (word == "v") {
      double x, y, z;
      s >> x >> y >> z;
      m.xyz.insert(m.xyz.end(), {x, y, z});
    } else if (word == "vt") {
      double u, v;
      s >> u >> v;
      m.uv.insert(m.uv.end(), {u, v});
    } else if (word == "f") {
      std::vector<int> v, vt;
      while (s >> word) {
        const auto slash = word.find('/');
        v.push_back(objIndex(word.substr(0, slash), static_cast<int>(m.xyz.size() / 3)));
        const std::string t = slash == std::string::npos ? "" : word.substr(slash + 1);
        const std::string t_index = t.substr(0, t.find('/'));
        vt.push_back(t_index.empty() ? -1 : objIndex(t_index, static_cast<int>(m.uv.size() / 2)));
      }
      for (size_t k = 1; k + 1 < v.size(); ++k) {
        const size_t corner[3] = {0, k, k + 1};
        bool textured = true;
        for (size_t c : corner) textured = textured && vt[c] >= 0;
        if (!textured) {
          ++m.faces_without_uv;
          continue;
        }
        for (size_t c : corner) {
          m.face_v.push_back(v[c]);
          m.face_vt.push_back(vt[c]);
        }
      }
    }
  }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: sdp_atlas_score RESULT.obj TEXTURE_SIZE GUTTER [--weld]\n");
    return 2;
  }
  try {
    const TexturedMesh m = readTexturedObj(argv[1]);
    const int texture_size = std::atoi(argv[2]);
    const int gutter = std::atoi(argv[3]);
    const bool weld = argc > 4 && std::string(argv[4]) == "--weld";
    const int vertex_count = static_cast<int>(m.xyz.size() / 3);
    std::vector<int> welded(vertex_count);
    std::map<std::array<double, 3>, int> first_at;
    int kept = 0;
    for (int v = 0; v < vertex_count; ++v) {
      const std::array<double, 3> p = {m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2]};
      if (!weld) {
        welded[v] = v;
        continue;
      }
      const auto [at, inserted] = first_at.emplace(p, kept);
      welded[v] = at->second;
      if (inserted) ++kept;
    }
    if (!weld) kept = vertex_count;
    sdp::Positions V(kept, 3);
    for (int v = 0; v < vertex_count; ++v)
      V.row(welded[v]) << m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2];
    const int faces = static_cast<int>(m.face_v.size() / 3);
    sdp::Triangles F(faces, 3);
    sdp::Layout layout;
    layout.face_uv.resize(faces, 3);
    layout.uv.resize(static_cast<int>(m.uv.size() / 2), 2);
    for (int i = 0; i < layout.uv.rows(); ++i) layout.uv.row(i) << m.uv[2 * i], m.uv[2 * i + 1];
    for (int f = 0; f < faces; ++f)
      for (int k = 0; k < 3; ++k) {
        F(f, k) = welded.at(m.face_v[3 * f + k]);
        layout.face_uv(f, k) = m.face_vt[3 * f + k];
        if (layout.face_uv(f, k) >= layout.uv.rows()) throw std::runtime_error("vt out of range");
      }
    const sdp::atlas::AtlasMeasures a =
        sdp::atlas::measureAtlas(V, F, layout, texture_size, gutter);
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
        "\"linf\": %s}\n",
        faces, a.charts, number(a.seam).c_str(), a.mirrored_charts, a.flipped_faces,
        a.overlapping_pixels, a.gutter_violations, a.outside_faces, m.faces_without_uv,
        number(a.efficiency).c_str(), number(a.l2).c_str(), number(a.linf).c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sdp_atlas_score: %s\n", e.what());
    return 1;
  }
}
