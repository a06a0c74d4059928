// The atlas (core/atlas): closed, higher-genus, many-piece, non-manifold and inconsistently
// oriented meshes made in code (and the shared closed models when they are there), each checked
// with the atlas measures on the stored values: every face charted, no flip, no mirrored chart,
// no pixel covered twice, every gutter kept, every UV in [0,1]^2, low stretch, the same bytes on
// every run; and bad input refused with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <thread>

#include "core/atlas/atlas.h"
#include "core/atlas/charts.h"
#include "core/atlas/convex_cut.h"
#include "core/atlas/measure.h"
#include "core/atlas/pack.h"
#include "core/atlas/planar_chart.h"
#include "core/atlas/raster.h"
#include "core/common/connectivity.h"
#include "core/common/error.h"
#include "core/common/geometry.h"
#include "core/common/metrics.h"
#include "io/mesh_io.h"
#include "scan_like_mesh.h"
#include "test_mesh_files.h"
#include "test_meshes.h"

namespace sdp::atlas {
namespace {

using test::Mesh;

// The mesh of vertices v and triangles f.
Mesh meshOf(const std::vector<Eigen::Vector3d>& v, const std::vector<std::array<int, 3>>& f) {
  Mesh mesh;
  mesh.V.resize(v.size(), 3);
  for (size_t i = 0; i < v.size(); ++i) mesh.V.row(i) = v[i].transpose();
  mesh.F.resize(f.size(), 3);
  for (size_t i = 0; i < f.size(); ++i) mesh.F.row(i) << f[i][0], f[i][1], f[i][2];
  return mesh;
}

// A torus of n x m quads (genus 1), radii R and r.
Mesh torus(int n, int m, double R = 1.0, double r = 0.4) {
  Mesh mesh;
  mesh.V.resize(n * m, 3);
  mesh.F.resize(2 * n * m, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * M_PI * i / n, v = 2 * M_PI * j / m;
      mesh.V.row(i * m + j) << (R + r * std::cos(v)) * std::cos(u),
          (R + r * std::cos(v)) * std::sin(u), r * std::sin(v);
    }
  int f = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const int a = i * m + j, b = ((i + 1) % n) * m + j, c = ((i + 1) % n) * m + (j + 1) % m,
                d = i * m + (j + 1) % m;
      mesh.F.row(f++) << a, b, c;
      mesh.F.row(f++) << a, c, d;
    }
  return mesh;
}

// A closed sphere: an octahedron split `levels` times, pushed onto the unit sphere.
Mesh sphere(int levels) {
  std::vector<Eigen::Vector3d> v = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                    {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  std::vector<std::array<int, 3>> f = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                       {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& t : f) {
      const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({ab, t[1], bc});
      next.push_back({ca, bc, t[2]});
      next.push_back({ab, bc, ca});
    }
    f.swap(next);
  }
  return meshOf(v, f);
}

// Both meshes in one (the second's vertices after the first's), moved apart along x.
Mesh together(const Mesh& a, const Mesh& b, double shift = 3) {
  Mesh m;
  m.V.resize(a.V.rows() + b.V.rows(), 3);
  m.V << a.V, b.V;
  m.V.bottomRows(b.V.rows()).col(0).array() += shift;
  m.F.resize(a.F.rows() + b.F.rows(), 3);
  m.F << a.F, (b.F.array() + static_cast<int>(a.V.rows())).matrix();
  return m;
}

AtlasOptions quickOptions(int texture_size = 1024) {
  AtlasOptions o;
  o.texture_size = texture_size;
  return o;
}

// The hard gates of an atlas as stored, measured from its layout alone.
void expectCertified(const Mesh& mesh, const AtlasResult& r, const AtlasOptions& o,
                     double l2_limit = 1.05) {
  // Faces wound against their neighbours are measured as the atlas charted them: turned over
  // (corners 1 and 2 swapped in the mesh and in the layout alike). Gates are then on that mesh.
  Triangles F = mesh.F;
  Layout layout = r.layout;
  if (o.turn_inconsistent_faces) {
    const std::vector<char> turn =
        coherentOrientation(F, analyzeConnectivity(F, static_cast<int>(mesh.V.rows())));
    EXPECT_EQ(std::count(turn.begin(), turn.end(), 1), r.report.faces_against_chart);
    for (int f = 0; f < F.rows(); ++f)
      if (turn[f])
        std::swap(F(f, 1), F(f, 2)), std::swap(layout.face_uv(f, 1), layout.face_uv(f, 2));
  }
  const AtlasMeasures m = measureAtlas(mesh.V, F, layout, o.texture_size, o.gutter);
  EXPECT_EQ(m.flipped_faces, 0);
  EXPECT_EQ(m.mirrored_charts, 0);
  EXPECT_EQ(m.overlapping_pixels, 0);
  EXPECT_EQ(m.gutter_violations, 0);
  EXPECT_EQ(m.outside_faces, 0);
  EXPECT_EQ(m.charts, r.report.charts);  // each chart one piece by its stored UVs
  ASSERT_EQ(r.layout.chart.size(), static_cast<size_t>(mesh.F.rows()));
  for (int c : r.layout.chart) EXPECT_GE(c, 0);
  EXPECT_LE(r.report.l2_stretch, l2_limit);
  EXPECT_NEAR(m.l2, r.report.l2_stretch, 1e-9);
  EXPECT_GT(r.report.packing_efficiency, 0.2);
  EXPECT_EQ(r.report.flipped_faces, 0);
  EXPECT_EQ(r.report.overlapping_charts, 0);
}

TEST(AtlasRaster, TwoTrianglesSharingAnEdgeCoverEachPixelOnce) {
  // The diagonal of a square passes through pixel centres: the top-left rule gives each one to
  // exactly one of the two triangles.
  const Eigen::Vector2d a(0, 0), b(8, 0), c(8, 8), d(0, 8);
  const Eigen::Vector2d t1[3] = {a, b, c}, t2[3] = {a, c, d};
  std::vector<int> count(64, 0);
  coveredPixels(t1, 8, 8, [&](int x, int y) { ++count[y * 8 + x]; });
  coveredPixels(t2, 8, 8, [&](int x, int y) { ++count[y * 8 + x]; });
  for (int n : count) EXPECT_EQ(n, 1);
}

TEST(AtlasRaster, SharedEdgesThroughCentresCoverEachPixelOnceWhateverTheRounding) {
  // Squares at arbitrary offsets and scales (as packing places them), split along a diagonal
  // that runs through pixel centres up to rounding: each centre still goes to one triangle.
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int trial = 0; trial < 2000; ++trial) {
    // Texel coordinates as uv * size, each a rounding away from the exact centre line.
    const double scale_x = 1 + unit(random), scale_y = 1 + unit(random);
    const double x0 = 3.5 / scale_x * scale_x, y0 = 3.5 / scale_y * scale_y;
    const double side = 4 + 20 * unit(random), offset = std::max(x0, y0);
    const Eigen::Vector2d a(x0, y0), b(x0 + side, y0), c(x0 + side, y0 + side), d(x0, y0 + side);
    const Eigen::Vector2d t1[3] = {a, b, c}, t2[3] = {a, c, d};
    std::vector<int> count(32 * 32, 0);
    coveredPixels(t1, 32, 32, [&](int x, int y) { ++count[y * 32 + x]; });
    coveredPixels(t2, 32, 32, [&](int x, int y) { ++count[y * 32 + x]; });
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        ASSERT_LE(count[y * 32 + x], 1) << "trial " << trial << " pixel " << x << "," << y;
        // A centre well inside the square, on or off the diagonal, is covered.
        const double cx = x + 0.5, cy = y + 0.5;
        if (cx > offset + 0.01 && cy > offset + 0.01 && cx < offset + side - 0.01 &&
            cy < offset + side - 0.01)
          ASSERT_EQ(count[y * 32 + x], 1) << "trial " << trial << " pixel " << x << "," << y;
      }
  }
}

TEST(AtlasRaster, CoveredPixelsAreThoseWhoseCentreLiesInside) {
  // Random triangles, slivers among them: each row's covered pixels are found from the run's
  // two ends only, so every centre clearly inside must be covered and every centre clearly
  // outside not (centres within 1e-6 texel of an edge go to one side by the top-left rule).
  std::mt19937 random(11);
  std::uniform_real_distribution<double> at(-4, 44);
  for (int trial = 0; trial < 3000; ++trial) {
    Eigen::Vector2d t[3] = {{at(random), at(random)}, {at(random), at(random)}, {0, 0}};
    // Every third a sliver: the third corner near the first edge's line.
    const double along = std::uniform_real_distribution<double>(0, 1)(random);
    t[2] = trial % 3 == 0 ? Eigen::Vector2d(t[0] + along * (t[1] - t[0]) +
                                            Eigen::Vector2d(0.3 * along, -0.2 * along))
                          : Eigen::Vector2d(at(random), at(random));
    const double twice_area = cross2(t[1] - t[0], t[2] - t[0]);
    if (std::abs(twice_area) < 1e-9) continue;
    std::vector<char> covered(40 * 40, 0);
    coveredPixels(t, 40, 40, [&](int x, int y) {
      ASSERT_FALSE(covered[y * 40 + x]) << "trial " << trial;
      covered[y * 40 + x] = 1;
    });
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) {
        const Eigen::Vector2d c(x + 0.5, y + 0.5);
        double least = std::numeric_limits<double>::infinity();  // signed distance to the edges
        for (int k = 0; k < 3; ++k) {
          const Eigen::Vector2d e = t[(k + 1) % 3] - t[k];
          least = std::min(least, (twice_area > 0 ? 1 : -1) * cross2(e, c - t[k]) / e.norm());
        }
        if (least > 1e-6)
          ASSERT_TRUE(covered[y * 40 + x]) << "trial " << trial << " " << x << "," << y;
        if (least < -1e-6)
          ASSERT_FALSE(covered[y * 40 + x]) << "trial " << trial << " " << x << "," << y;
      }
  }
}

TEST(AtlasRaster, ConservativeCellsHoldEveryCoveredPixel) {
  const Eigen::Vector2d t[3] = {{0.3, 0.2}, {7.6, 1.1}, {2.2, 6.9}};
  std::vector<char> cells(100, 0);
  conservativeCells(t, 0, 10, 10, [&](int x, int y) { cells[y * 10 + x] = 1; });
  int covered = 0;
  coveredPixels(t, 10, 10, [&](int x, int y) {
    EXPECT_TRUE(cells[y * 10 + x]) << x << "," << y;
    ++covered;
  });
  EXPECT_GT(covered, 10);
}

TEST(AtlasMeasures, PixelBandsCountAsOneRasterOfTheWholeTexture) {
  // Triangles across many 64-row bands, overlapping and near each other: the banded, parallel
  // count (in runs of pixels) equals a direct count over the whole texture, pixel by pixel. Few
  // large triangles, and many small ones (many short runs per row).
  const int size = 300;
  for (const auto& [triangles, extent] : {std::pair<int, double>{40, 1.0}, {3000, 0.03}}) {
    Layout layout;
    layout.uv.resize(3 * triangles, 2);
    layout.face_uv.resize(triangles, 3);
    std::vector<int> chart(triangles);
    unsigned state = 12345;
    auto next = [&] { return (state = state * 1103515245u + 12345u) / 4294967296.0; };
    for (int f = 0; f < triangles; ++f) {
      const double x = next() * (1 - extent), y = next() * (1 - extent);
      for (int k = 0; k < 3; ++k) {
        layout.uv.row(3 * f + k) << x + extent * next(), y + extent * next();
        layout.face_uv(f, k) = 3 * f + k;
      }
      chart[f] = f % 7;
    }
    std::vector<int> covers(size * size, 0), owner(size * size, -1);
    for (int f = 0; f < triangles; ++f) {
      Eigen::Vector2d q[3];
      for (int k = 0; k < 3; ++k) q[k] = (layout.corner(f, k) * size).transpose();
      coveredPixels(q, size, size, [&](int x, int y) {
        ++covers[y * size + x];
        int& o = owner[y * size + x];
        o = o == -1 || o == chart[f] ? chart[f] : -2;
      });
    }
    for (const int gutter : {1, 2, 3, 6}) {
      // The measure works in bands of rows with halos of gutter - 1 rows; this counts directly.
      const int reach = gutter - 1;
      long long overlapping = 0, violations = 0;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const int c = owner[y * size + x];
          overlapping += covers[y * size + x] >= 2;
          if (c == -1 || reach == 0) continue;
          bool bad = c == -2;
          for (int dy = -reach; dy <= reach; ++dy)
            for (int dx = -reach; dx <= reach; ++dx) {
              const int nx = x + dx, ny = y + dy;
              if (nx < 0 || ny < 0 || nx >= size || ny >= size) continue;
              const int o = owner[ny * size + nx];
              bad = bad || (o != -1 && o != c);
            }
          violations += bad;
        }
      const PixelMeasures m = measurePixels(layout, chart, size, gutter);
      EXPECT_GT(overlapping, 1000) << triangles;
      EXPECT_EQ(m.overlapping_pixels, overlapping) << triangles << " " << gutter;
      EXPECT_EQ(m.gutter_violations, violations) << triangles << " " << gutter;
      if (reach > 0) EXPECT_GT(violations, overlapping) << triangles << " " << gutter;
    }
  }
}

TEST(AtlasMeasures, CountOverlapGutterSeamAndMirroredCharts) {
  // Two triangles of two charts (no shared UVs across their shared edge).
  Mesh mesh;
  mesh.V.resize(4, 3);
  mesh.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  mesh.F.resize(2, 3);
  mesh.F << 0, 1, 2, 0, 2, 3;
  Layout layout;
  layout.uv.resize(6, 2);
  layout.uv << 0.1, 0.1, 0.4, 0.1, 0.4, 0.4,  // chart 0
      0.5, 0.1, 0.8, 0.4, 0.5, 0.4;           // chart 1, a gap of 0.1 from chart 0
  layout.face_uv.resize(2, 3);
  layout.face_uv << 0, 1, 2, 3, 4, 5;
  AtlasMeasures m = measureAtlas(mesh.V, mesh.F, layout, 100, 2);
  EXPECT_EQ(m.charts, 2);
  EXPECT_NEAR(m.seam, std::sqrt(2.0), 1e-12);  // the diagonal, over sqrt(area 1)
  EXPECT_EQ(m.overlapping_pixels, 0);
  EXPECT_EQ(m.gutter_violations, 0);
  EXPECT_EQ(m.mirrored_charts, 0);
  EXPECT_EQ(m.flipped_faces, 0);
  // Chart 1 moved onto chart 0: overlapping pixels; next to it: gutter violations.
  layout.uv.bottomRows(3).col(0).array() -= 0.3;
  m = measureAtlas(mesh.V, mesh.F, layout, 100, 2);
  EXPECT_GT(m.overlapping_pixels, 0);
  EXPECT_GT(m.gutter_violations, 0);
  // Mirrored: chart 1 reflected.
  layout.uv.bottomRows(3).col(0) = 1.0 - layout.uv.bottomRows(3).col(0).array();
  m = measureAtlas(mesh.V, mesh.F, layout, 100, 2);
  EXPECT_EQ(m.mirrored_charts, 1);
  // One chart: the same UVs on both sides of the diagonal, no seam.
  Layout one =
      Layout::perVertex((Eigen::MatrixXd(4, 2) << 0, 0, 1, 0, 1, 1, 0, 1).finished(), mesh.F);
  m = measureAtlas(mesh.V, mesh.F, one, 0, 0);
  EXPECT_EQ(m.charts, 1);
  EXPECT_EQ(m.seam, 0);
  EXPECT_NEAR(m.efficiency, 1.0, 1e-12);
}

TEST(Atlas, ClosedSphere) {
  const Mesh mesh = sphere(4);  // 2048 faces
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
  EXPECT_GE(r.report.charts, 2);  // a closed sphere needs a cut
  EXPECT_LE(r.report.charts, 40);
  EXPECT_EQ(r.report.components, 1);
}

TEST(Atlas, TorusOfGenusOne) {
  const Mesh mesh = torus(48, 16);
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
  EXPECT_GE(r.report.charts, 1);
}

TEST(Atlas, SeveralPiecesOpenAndClosed) {
  const Mesh mesh = together(together(sphere(3), torus(32, 12)), test::planarGrid(10), 6);
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
  EXPECT_EQ(r.report.components, 3);
  // The flat grid is one chart, with a texel density shared by all charts.
  EXPECT_GT(r.report.texels_per_unit, 0);
}

TEST(Atlas, InconsistentOrientationIsCutNeverMirroredWhenFacesAreNotTurned) {
  Mesh mesh = sphere(3);
  for (int f = 0; f < mesh.F.rows(); f += 7) std::swap(mesh.F(f, 1), mesh.F(f, 2));
  AtlasOptions o = quickOptions();
  o.turn_inconsistent_faces = false;
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
  EXPECT_GT(r.report.inconsistent_edges, 0);
  EXPECT_EQ(r.report.faces_against_chart, 0);
  EXPECT_TRUE(r.report.warnings.empty());
}

TEST(Atlas, FacesWoundAgainstTheirNeighboursAreChartedAsTheSurfaceRuns) {
  const Mesh consistent = sphere(3);
  Mesh mesh = consistent;
  int swapped = 0;
  for (int f = 0; f < mesh.F.rows(); f += 3) std::swap(mesh.F(f, 1), mesh.F(f, 2)), ++swapped;
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  const AtlasResult expected = makeAtlas(consistent.V, consistent.F, o);
  // The minority turned back: the consistent sphere's atlas exactly, each turned face's corners
  // in its own order (so its texture triangle runs clockwise), counted and warned about.
  EXPECT_EQ(r.report.faces_against_chart, swapped);
  EXPECT_GT(r.report.inconsistent_edges, 0);
  EXPECT_EQ(r.report.charts, expected.report.charts);
  EXPECT_EQ(r.report.flipped_faces, 0);
  ASSERT_EQ(r.report.warnings.size(), 1u);
  EXPECT_NE(r.report.warnings[0].find(std::to_string(swapped) + " faces are wound against"),
            std::string::npos);
  EXPECT_NE(r.report.warnings[0].find("meshing_re_orient_faces_coherently"), std::string::npos);
  EXPECT_EQ(r.layout.uv, expected.layout.uv);
  Triangles corners_back = r.layout.face_uv;
  for (int f = 0; f < mesh.F.rows(); f += 3) std::swap(corners_back(f, 1), corners_back(f, 2));
  EXPECT_EQ(corners_back, expected.layout.face_uv);
  // As stored, no pixel is covered twice and the gutter holds; the turned faces run clockwise.
  const AtlasMeasures m = measureAtlas(mesh.V, mesh.F, r.layout, o.texture_size, o.gutter);
  EXPECT_EQ(m.overlapping_pixels, 0);
  EXPECT_EQ(m.gutter_violations, 0);
  EXPECT_EQ(m.charts, r.report.charts);
}

TEST(Atlas, AMoebiusStripKeepsTheEdgeWhereItsWalkMeetsItselfCut) {
  // A strip of quads closed with a half twist: no winding agrees everywhere.
  Mesh mesh;
  const int n = 24;
  mesh.V.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n, twist = a / 2;
    for (int s = 0; s < 2; ++s) {
      const double r = 1 + (s ? 0.25 : -0.25) * std::cos(twist);
      mesh.V.row(2 * i + s) << r * std::cos(a), r * std::sin(a),
          (s ? 0.25 : -0.25) * std::sin(twist);
    }
  }
  mesh.F.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    const int a = 2 * i, b = 2 * i + 1;
    // The last quad joins the first column upside down (the half twist).
    const int c = i + 1 < n ? 2 * (i + 1) : 1, d = i + 1 < n ? 2 * (i + 1) + 1 : 0;
    mesh.F.row(2 * i) << a, c, d;
    mesh.F.row(2 * i + 1) << a, d, b;
  }
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  EXPECT_EQ(r.report.flipped_faces, 0);
  EXPECT_GE(r.report.charts, 1);
  const AtlasMeasures m = measureAtlas(mesh.V, mesh.F, r.layout, o.texture_size, o.gutter);
  EXPECT_EQ(m.overlapping_pixels, 0);
  EXPECT_EQ(m.gutter_violations, 0);
}

TEST(Atlas, NonManifoldEdgeAndZeroAreaFacesAreCharted) {
  Mesh mesh = test::planarGrid(6);
  const int n = static_cast<int>(mesh.V.rows());
  // A fin on an inner edge (three faces on it), and a zero-area face (collinear corners) and
  // a face with a repeated vertex.
  mesh.V.conservativeResize(n + 2, 3);
  mesh.V.row(n) << 0.5, 0.5, 1;
  mesh.V.row(n + 1) = 0.5 * (mesh.V.row(0) + mesh.V.row(1));
  const int faces = static_cast<int>(mesh.F.rows());
  mesh.F.conservativeResize(faces + 3, 3);
  mesh.F.row(faces) << mesh.F(10, 0), mesh.F(10, 1), n;
  mesh.F.row(faces + 1) << 0, n + 1, 1;
  mesh.F.row(faces + 2) << 2, 2, 3;
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
  EXPECT_EQ(r.report.non_manifold_edges, 1);
  EXPECT_EQ(r.report.zero_area_faces, 2);
  // Zero-area faces still get a positive UV area.
  for (int f : {faces + 1, faces + 2}) {
    const Eigen::RowVector2d a = r.layout.corner(f, 0), b = r.layout.corner(f, 1),
                             c = r.layout.corner(f, 2);
    EXPECT_GT((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x(), 0);
  }
}

TEST(Atlas, SameBytesOnEveryRunAndEveryStorage) {
  const Mesh mesh = together(sphere(3), torus(32, 12));
  for (UVStorage storage : {UVStorage::Double, UVStorage::Float, UVStorage::FloatAndSixDecimals}) {
    AtlasOptions o = quickOptions();
    o.storage = storage;
    const AtlasResult a = makeAtlas(mesh.V, mesh.F, o);
    const AtlasResult b = makeAtlas(mesh.V, mesh.F, o);
    ASSERT_EQ(a.layout.uv.rows(), b.layout.uv.rows());
    EXPECT_EQ(0, std::memcmp(a.layout.uv.data(), b.layout.uv.data(),
                             sizeof(double) * a.layout.uv.size()));
    EXPECT_TRUE(a.layout.face_uv == b.layout.face_uv);
    expectCertified(mesh, a, o);
    for (int i = 0; i < a.layout.uv.size(); ++i) {
      const double x = a.layout.uv.data()[i];
      if (storage != UVStorage::Double) EXPECT_EQ(x, static_cast<double>(static_cast<float>(x)));
    }
  }
}

TEST(Atlas, ASpatiallyOrderedCopyIsGivenBackInTheInputsOrder) {
  // From spatial_order_faces faces the atlas charts a copy in a spatial order (atlas.h); here
  // from any size, on faces written in random order, some wound against their neighbours and
  // a vertex left unused: every per-face value comes back on the input's own face.
  Mesh mesh = together(sphere(3), torus(32, 12));
  std::vector<int> order(mesh.F.rows());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), std::mt19937(7));
  Triangles shuffled(mesh.F.rows(), 3);
  for (int f = 0; f < mesh.F.rows(); ++f) shuffled.row(f) = mesh.F.row(order[f]);
  for (int f = 0; f < shuffled.rows(); f += 7) std::swap(shuffled(f, 1), shuffled(f, 2));
  mesh.F = shuffled;
  mesh.V.conservativeResize(mesh.V.rows() + 1, 3);
  mesh.V.row(mesh.V.rows() - 1) = Eigen::RowVector3d(5, 5, 5);
  AtlasOptions o = quickOptions();
  o.spatial_order_faces = 0;
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
  EXPECT_GT(r.report.faces_against_chart, 0);
  // The per-face stretch is the input face's: measured anew on the layout as given back.
  Triangles F = mesh.F;
  Layout layout = r.layout;
  const std::vector<char> turn =
      coherentOrientation(F, analyzeConnectivity(F, static_cast<int>(mesh.V.rows())));
  for (int f = 0; f < F.rows(); ++f)
    if (turn[f]) std::swap(F(f, 1), F(f, 2)), std::swap(layout.face_uv(f, 1), layout.face_uv(f, 2));
  const StretchMetrics s = layoutStretch(mesh.V, F, layout);
  ASSERT_EQ(r.face_stretch.size(), s.face_l2.size());
  for (size_t f = 0; f < s.face_l2.size(); ++f) EXPECT_NEAR(r.face_stretch[f], s.face_l2[f], 1e-9);
  // The same bytes on a second run; and charted in the input's order, still certified.
  const AtlasResult again = makeAtlas(mesh.V, mesh.F, o);
  EXPECT_TRUE(again.layout.uv == r.layout.uv);
  EXPECT_TRUE(again.layout.face_uv == r.layout.face_uv);
  o.spatial_order_faces = std::numeric_limits<int>::max();
  expectCertified(mesh, makeAtlas(mesh.V, mesh.F, o), o);
}

// From reweight_below_faces faces the charts' refinement skips the reweighting steps on the fixed
// boundary (atlas.h): none of their work is counted, the free-boundary steps still refine, and
// the atlas keeps every gate.
TEST(Atlas, LargeMeshesRefineTheirChartsWithoutReweighting) {
  const Mesh mesh = together(sphere(3), torus(24, 10));
  auto work = [](const AtlasResult& r, const std::string& key) {
    for (const auto& [name, value] : r.report.stage_work)
      if (name == key) return value;
    return 0.0;
  };
  AtlasOptions o = quickOptions();
  const AtlasResult reweighted = makeAtlas(mesh.V, mesh.F, o);
  EXPECT_GT(work(reweighted, "refine"), 0);
  o.reweight_below_faces = 0;
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
  EXPECT_EQ(work(r, "refine"), 0);
  EXPECT_GT(work(r, "free_boundary") + work(r, "newton"), 0);
  EXPECT_LE(r.report.l2_stretch, 1.03);
}

TEST(Atlas, GutterIsKeptAtEveryWidth) {
  const Mesh mesh = together(sphere(3), torus(24, 10));
  for (int gutter : {0, 1, 4, 8}) {
    AtlasOptions o = quickOptions(512);
    o.gutter = gutter;
    const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
    expectCertified(mesh, r, o);
  }
}

// The input's check runs on every core in slices of faces: the reason given is still that of
// the first bad face in the mesh's order, whichever slice finds one first.
TEST(Atlas, TheFirstBadFaceOfALargeMeshIsTheOneNamed) {
  const int faces = 100000;
  Positions V(faces + 2, 3);
  for (int v = 0; v < faces + 2; ++v) V.row(v) << v, v % 2, 0;
  Triangles F(faces, 3);
  for (int f = 0; f < faces; ++f) F.row(f) << f, f + 1, f + 2;
  F(90000, 1) = faces + 7;     // out of range, late
  V(70001, 2) = std::nan("");  // not finite, at faces 69999 ... 70001
  F(80000, 0) = -1;            // out of range, between them
  try {
    makeAtlas(V, F, AtlasOptions{});
    ADD_FAILURE() << "accepted";
  } catch (const ParameterizationError& e) {
    EXPECT_STREQ(e.what(), "vertex 70001 has a coordinate that is not finite");
  }
  V(70001, 2) = 0;
  try {
    makeAtlas(V, F, AtlasOptions{});
    ADD_FAILURE() << "accepted";
  } catch (const ParameterizationError& e) {
    EXPECT_STREQ(e.what(),
                 "face 80000 has vertex index -1 out of range (the mesh has 100002 vertices)");
  }
}

TEST(Atlas, BadInputIsRefusedWithOneLine) {
  auto reason = [](const Positions& V, const Triangles& F, AtlasOptions o = {}) {
    try {
      makeAtlas(V, F, o);
    } catch (const ParameterizationError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  Positions V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  Triangles none(0, 3);
  EXPECT_EQ(reason(V, none), "the mesh has no faces");
  Triangles F(1, 3);
  F << 0, 1, 5;
  EXPECT_NE(reason(V, F).find("out of range"), std::string::npos);
  F << 0, 1, 2;
  Positions nan = V;
  nan(1, 1) = std::nan("");
  EXPECT_NE(reason(nan, F).find("not finite"), std::string::npos);
  Positions line(3, 3);
  line << 0, 0, 0, 1, 0, 0, 2, 0, 0;
  EXPECT_EQ(reason(line, F), "every face has zero area (no surface to flatten)");
  AtlasOptions small;
  small.texture_size = 8;
  EXPECT_NE(reason(V, F, small).find("texture size"), std::string::npos);
  for (const std::string& r : {reason(V, none), reason(line, F)})
    EXPECT_EQ(r.find('\n'), std::string::npos);
}

// A triangle soup with more pieces than the texture has room for charts is refused at the
// start, before any chart is flattened (progress never passes 0), with what to change.
TEST(Atlas, MorePiecesThanTheTextureHoldsAreRefusedBeforeCharting) {
  auto soup = [](int triangles, Positions& V, Triangles& F) {
    V.resize(3 * triangles, 3);
    F.resize(triangles, 3);
    for (int t = 0; t < triangles; ++t) {
      V.row(3 * t) << 2.0 * t, 0, 0;
      V.row(3 * t + 1) << 2.0 * t + 1, 0, 0;
      V.row(3 * t + 2) << 2.0 * t, 1, 0;
      F.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
    }
  };
  AtlasOptions o;
  o.texture_size = 64;
  o.gutter = 2;  // room for at most 32 x 32 charts
  int highest = -1;
  o.chart.progress = [&highest](const char*, int percent) {
    highest = std::max(highest, percent);
    return true;
  };
  Positions V;
  Triangles F;
  soup(1025, V, F);
  try {
    makeAtlas(V, F, o);
    ADD_FAILURE() << "accepted";
  } catch (const ParameterizationError& e) {
    const std::string why = e.what();
    EXPECT_NE(why.find("at least 1025 charts"), std::string::npos) << why;
    EXPECT_NE(why.find("(1024)"), std::string::npos) << why;
    EXPECT_NE(why.find("raise the texture size"), std::string::npos) << why;
    EXPECT_EQ(why.find('\n'), std::string::npos);
  }
  EXPECT_LE(highest, 4);  // the connectivity's share of the bar: no chart was cut or flattened
  // With a texture twice as wide the same soup is charted.
  o.texture_size = 128;
  EXPECT_EQ(makeAtlas(V, F, o).report.charts, 1025);
}

TEST(Atlas, ProgressRisesToAHundredOnTheCallingThreadOnly) {
  // Front ends redraw their bar in the callback, which is not thread-safe: every call comes from
  // the thread that called makeAtlas, the percentage never falls, and it moves through the run.
  const Mesh mesh = sphere(5);
  AtlasOptions o = quickOptions();
  std::vector<int> seen;
  bool other_thread = false;
  const std::thread::id caller = std::this_thread::get_id();
  o.chart.progress = [&](const char* stage, int percent) {
    other_thread |= std::this_thread::get_id() != caller;
    EXPECT_STREQ(stage, "atlas");
    seen.push_back(percent);
    return true;
  };
  makeAtlas(mesh.V, mesh.F, o);
  EXPECT_FALSE(other_thread);
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.front(), 0);
  EXPECT_EQ(seen.back(), 100);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_GE(std::set<int>(seen.begin(), seen.end()).size(), 8u);
}

TEST(Atlas, CancelStopsTheRun) {
  const Mesh mesh = sphere(3);
  AtlasOptions o = quickOptions();
  o.chart.progress = [](const char*, int percent) { return percent < 5; };
  EXPECT_THROW(makeAtlas(mesh.V, mesh.F, o), ParameterizationError);
}

// A flat strip much longer than the square root of its area is halved across its length, and
// each half keeps its part of the strip's map (no second flattening): the halves are labelled
// "part of ..." and are within the kept-map limits.
TEST(Atlas, PiecesCutOutOfAChartKeepItsMap) {
  const int length = 48, width = 4;
  Mesh mesh;
  mesh.V.resize((length + 1) * (width + 1), 3);
  for (int i = 0; i <= length; ++i)
    for (int j = 0; j <= width; ++j) mesh.V.row(i * (width + 1) + j) << i, j, 0;
  mesh.F.resize(2 * length * width, 3);
  int f = 0;
  for (int i = 0; i < length; ++i)
    for (int j = 0; j < width; ++j) {
      const int a = i * (width + 1) + j, b = a + width + 1;
      mesh.F.row(f++) << a, b, b + 1;
      mesh.F.row(f++) << a, b + 1, a + 1;
    }
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o, 1.0 + 1e-9);
  EXPECT_GE(r.report.charts, 2);
  int kept = 0;
  for (const ChartReport& chart : r.report.chart_table) {
    if (chart.boundary_used.rfind("part of ", 0) != 0) continue;
    ++kept;
    EXPECT_LE(chart.l2_stretch, o.max_chart_stretch);
    EXPECT_LE(chart.linf_stretch, 2.0);
  }
  EXPECT_EQ(kept, r.report.charts);  // every piece came from the one flattened strip
}

// A closed box of sides sx, sy, sz, each side an n x n grid of squares cut into two triangles
// (vertices shared along the edges), faces wound outwards.
Mesh box(int n, double sx, double sy, double sz) {
  std::map<std::array<long, 3>, int> index;
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<int, 3>> f;
  auto vertex = [&](const std::array<long, 3>& g) {
    auto [it, added] = index.emplace(g, static_cast<int>(v.size()));
    if (added) v.emplace_back(sx * g[0] / n, sy * g[1] / n, sz * g[2] / n);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const int u = (axis + 1) % 3, w = (axis + 2) % 3;
          auto corner = [&](int a, int b) {
            std::array<long, 3> g{};
            g[axis] = side * n, g[u] = i + a, g[w] = j + b;
            return vertex(g);
          };
          const int p = corner(0, 0), q = corner(1, 0), r = corner(1, 1), t = corner(0, 1);
          if (side == 1) {
            f.push_back({p, q, r});
            f.push_back({p, r, t});
          } else {
            f.push_back({p, r, q});
            f.push_back({p, t, r});
          }
        }
  return meshOf(v, f);
}

// A mesh with its connectivity, its face graph, every face listed and a scratch for them; built
// in place and never copied, as the graph points into the mesh.
struct MeshGraph {
  explicit MeshGraph(Mesh m)
      : mesh(std::move(m)),
        connectivity(analyzeConnectivity(mesh.F, static_cast<int>(mesh.V.rows()))),
        graph(buildFaceGraph(mesh.V, mesh.F, connectivity)),
        faces(mesh.F.rows()),
        scratch(graph) {
    std::iota(faces.begin(), faces.end(), 0);
  }
  MeshGraph(const MeshGraph&) = delete;
  MeshGraph& operator=(const MeshGraph&) = delete;
  const Mesh mesh;
  const Connectivity connectivity;
  const FaceGraph graph;
  std::vector<int> faces;
  FaceScratch scratch;
};

TEST(AtlasCharts, FeaturePatchesFollowSharpEdgesAndAbsorbSmallOnes) {
  MeshGraph m(box(6, 1, 2, 3));
  const double sharp = std::cos(40.0 * M_PI / 180);
  const auto sides = featurePatches(m.graph, m.faces, sharp, 1, m.scratch);
  ASSERT_EQ(sides.size(), 6u);  // one per side of the box, each flat
  for (const auto& side : sides) {
    EXPECT_EQ(side.size(), 72u);
    for (int f : side) EXPECT_GT(m.graph.normal[f].dot(m.graph.normal[side.front()]), 1 - 1e-12);
  }
  // Sides smaller than `fewest` join their neighbours: nothing is left alone.
  const auto joined = featurePatches(m.graph, m.faces, sharp, 100, m.scratch);
  EXPECT_LT(joined.size(), 6u);
  size_t total = 0;
  for (const auto& part : joined) total += part.size();
  EXPECT_EQ(total, m.faces.size());
  for (int f : m.faces) EXPECT_EQ(m.scratch.region[f], kOutside);
  // The 1 x 2 x 3 box's sides have areas 2, 3 and 6, two of each: the second largest holds 6 of
  // 22; counted only from 100 faces (72 each), none does.
  EXPECT_NEAR(secondFeaturePatchShare(m.graph, m.faces, sharp, 1, m.scratch), 6.0 / 22, 1e-12);
  EXPECT_EQ(secondFeaturePatchShare(m.graph, m.faces, sharp, 100, m.scratch), 0.0);
  for (int f : m.faces) EXPECT_EQ(m.scratch.region[f], kOutside);
}

TEST(AtlasCharts, EulerCharacteristicOfRegionsMatchesTheirMesh) {
  // A closed box (2), one side (a disk: 1) and the four sides around it (a ring: 0): the count by
  // the graph's joins, against regionHoles, which builds each region's own mesh.
  MeshGraph m(box(6, 1, 2, 3));
  EXPECT_EQ(regionEulerCharacteristic(m.graph, m.faces, m.scratch), 2);
  const auto sides = featurePatches(m.graph, m.faces, std::cos(40.0 * M_PI / 180), 1, m.scratch);
  ASSERT_EQ(sides.size(), 6u);
  EXPECT_EQ(regionEulerCharacteristic(m.graph, sides[0], m.scratch), 1);
  EXPECT_EQ(regionHoles(m.graph, sides[0], m.scratch), 0);
  // The four sides that do not face the first one's way or the opposite.
  std::vector<int> ring;
  for (const auto& side : sides)
    if (std::abs(m.graph.normal[side[0]].dot(m.graph.normal[sides[0][0]])) < 0.5)
      ring.insert(ring.end(), side.begin(), side.end());
  std::sort(ring.begin(), ring.end());
  ASSERT_EQ(ring.size(), 4 * 72u);
  EXPECT_EQ(regionEulerCharacteristic(m.graph, ring, m.scratch), 0);
  EXPECT_EQ(regionHoles(m.graph, ring, m.scratch), 1);
  for (int f : m.faces) EXPECT_EQ(m.scratch.region[f], kOutside);
  for (int v = 0; v < m.mesh.V.rows(); ++v) EXPECT_EQ(m.scratch.vertex[v], -1);
}

TEST(AtlasCharts, FlatPatchesSeparateFacesAFilletJoins) {
  // A sheet bent by 60 degrees through a fillet over a fifth of its width (about 10 degrees per
  // edge): no sharp edge, so one feature patch, but the two flat legs face apart.
  const double slope = std::tan(60.0 * M_PI / 180);
  MeshGraph m(test::grid(30, 1.0, 1.0, [&](double x, double) {
    if (x <= 0.4) return 0.0;
    if (x >= 0.6) return slope * (x - 0.5);
    return slope * (x - 0.4) * (x - 0.4) / 0.4;  // the slope grows linearly across the fillet
  }));
  EXPECT_EQ(featurePatches(m.graph, m.faces, std::cos(40.0 * M_PI / 180), 20, m.scratch).size(),
            1u);
  const auto flats = flatPatches(m.graph, m.faces, std::cos(20.0 * M_PI / 180), 20, m.scratch);
  ASSERT_GE(flats.size(), 2u);
  size_t total = 0;
  for (const auto& patch : flats) {
    total += patch.size();
    bool left = false, right = false;  // a face on each flat leg
    for (int f : patch) {
      const double x = m.graph.centroid[f].x();
      left |= x<0.35, right |= x> 0.65;
    }
    EXPECT_FALSE(left && right);
  }
  EXPECT_EQ(total, m.faces.size());
  for (int f : m.faces) EXPECT_EQ(m.scratch.region[f], kOutside);
}

TEST(Atlas, ABoxIsUnfoldedAlongItsEdgesWithoutStretch) {
  const Mesh mesh = box(8, 1, 2, 3);
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
  // Charts are cut along the box's edges and merged only where the sides unfold flat.
  EXPECT_LE(r.report.charts, 6);
  EXPECT_LT(r.report.linf_stretch, 1.01);
}

// A flat sheet of n x n quads over [0, 1]^2 with the quads (i, j) of `removed` cut out.
Mesh sheetWithHoles(int n, const std::vector<std::pair<int, int>>& removed) {
  const Mesh grid = test::grid(n, 1.0, 1.0, [](double, double) { return 0.0; });
  std::vector<int> kept;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (std::find(removed.begin(), removed.end(), std::make_pair(i, j)) == removed.end())
        kept.insert(kept.end(), {2 * (j * n + i), 2 * (j * n + i) + 1});
  Mesh mesh;
  mesh.V = grid.V;
  mesh.F.resize(kept.size(), 3);
  for (size_t f = 0; f < kept.size(); ++f) mesh.F.row(f) = grid.F.row(kept[f]);
  return mesh;
}

// `mesh` with a square of side `side` beside it (two triangles at height z = 5): a piece of its
// own, so that what the test looks at is not the whole mesh's area.
Mesh withSquareBeside(Mesh mesh, double side) {
  const int first = static_cast<int>(mesh.V.rows());
  mesh.V.conservativeResize(first + 4, 3);
  mesh.V.bottomRows(4) << 0, 0, 5, side, 0, 5, side, side, 5, 0, side, 5;
  mesh.F.conservativeResize(mesh.F.rows() + 2, 3);
  mesh.F.bottomRows(2) << first, first + 1, first + 2, first, first + 2, first + 3;
  return mesh;
}

// A long flat fan of slivers, every face reaching from a short curved end to one far vertex (a
// CAD part's flat face triangulated end to end), with a square beside it: every centroid lies
// in the first third of the fan's length, so the halving across the middle would leave one side
// empty and the fan whole. It is cut through the centroids instead.
TEST(Atlas, ALongChartOfSliversIsStillCut) {
  const int ends = 33;  // vertices on the curved end
  Mesh fan;
  fan.V.resize(ends + 1, 3);
  for (int j = 0; j < ends; ++j)
    fan.V.row(j) << 2 * std::sin(kPi * j / (ends - 1)), 8.0 * j / (ends - 1), 0;
  fan.V.row(ends) << 96, 4, 0;
  fan.F.resize(ends - 1, 3);
  for (int j = 0; j + 1 < ends; ++j) fan.F.row(j) << j, ends, j + 1;
  const Mesh mesh = withSquareBeside(fan, 40);
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o, 1.0 + 1e-9);
  EXPECT_GE(r.report.charts, 3);  // the square, and the fan in two pieces or more
}

TEST(Atlas, ASheetWithSmallHolesIsOneChartAndARingIsCut) {
  // Holes of one quad each, far less than the sheet's area: the sheet is flattened whole, its
  // holes filled for the solve, so no seam runs from hole to hole.
  // Beside it a square of its own, so that the sheet is not the whole mesh (a chart longer than
  // the square root of the mesh's area is halved for packing).
  const Mesh drilled =
      withSquareBeside(sheetWithHoles(16, {{4, 4}, {11, 4}, {4, 11}, {11, 11}, {8, 8}}), 1);
  const AtlasOptions o = quickOptions();
  const AtlasResult sheet = makeAtlas(drilled.V, drilled.F, o);
  expectCertified(drilled, sheet, o);
  EXPECT_EQ(sheet.report.charts, 2);
  EXPECT_EQ(sheet.report.seam, 0);
  EXPECT_LT(sheet.report.linf_stretch, 1.01);
  // A ring (the middle 12 x 12 quads cut out) would leave its middle empty in the texture.
  std::vector<std::pair<int, int>> middle;
  for (int j = 2; j < 14; ++j)
    for (int i = 2; i < 14; ++i) middle.emplace_back(i, j);
  const Mesh ring = sheetWithHoles(16, middle);
  const AtlasResult cut = makeAtlas(ring.V, ring.F, o);
  expectCertified(ring, cut, o);
  EXPECT_GE(cut.report.charts, 2);
}

// A thick-walled tube (a drilled hole's wall inside, a shaft's outside): two cylinders of n
// sides and `rows` rows over height h, joined by flat rings at both ends, every rim a sharp edge,
// faces wound outwards (into the hole on the inner wall).
Mesh thickTube(int n, int rows, double inner, double outer, double h) {
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<int, 3>> f;
  // Rings of vertices: inner wall rows 0..rows, then outer wall rows 0..rows.
  auto at = [&](int wall, int row, int i) { return (wall * (rows + 1) + row) * n + (i % n); };
  for (int wall = 0; wall < 2; ++wall)
    for (int row = 0; row <= rows; ++row)
      for (int i = 0; i < n; ++i) {
        const double angle = 2 * kPi * i / n, radius = wall == 0 ? inner : outer;
        v.emplace_back(radius * std::cos(angle), radius * std::sin(angle), h * row / rows);
      }
  // The quad a b c d counter-clockwise seen from the side its normal points to.
  auto quad = [&](int a, int b, int c, int d) {
    f.push_back({a, b, c});
    f.push_back({a, c, d});
  };
  for (int i = 0; i < n; ++i) {
    for (int row = 0; row < rows; ++row) {
      quad(at(1, row, i), at(1, row, i + 1), at(1, row + 1, i + 1), at(1, row + 1, i));
      quad(at(0, row, i + 1), at(0, row, i), at(0, row + 1, i), at(0, row + 1, i + 1));
    }
    quad(at(0, rows, i), at(0, rows, i + 1), at(1, rows, i + 1), at(1, rows, i));  // top
    quad(at(0, 0, i + 1), at(0, 0, i), at(1, 0, i), at(1, 0, i + 1));              // bottom
  }
  Mesh mesh = meshOf(v, f);
  return mesh;
}

TEST(AtlasCharts, ADevelopableDiskIsUnrolledExactlyACurvedOneIsNot) {
  // Half of a cylinder's wall (a disk): its inner vertices have no angle defect.
  const Mesh tube = thickTube(24, 3, 0.5, 1.0, 0.4);
  std::vector<int> half;
  for (int i = 0; i < 12; ++i)
    for (int k = 0; k < 6; ++k) half.push_back(i * 16 + 4 * (k / 2) + k % 2);  // outer wall
  Triangles F(half.size(), 3);
  for (size_t f = 0; f < half.size(); ++f) F.row(f) = tube.F.row(half[f]);
  // Its own vertices only, as a chart's are.
  std::map<int, int> row;
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) row.emplace(F(f, k), static_cast<int>(row.size()));
  Positions V(row.size(), 3);
  for (const auto& [from, to] : row) V.row(to) = tube.V.row(from);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) F(f, k) = row.at(F(f, k));
  const std::optional<std::vector<Eigen::Vector2d>> uv = unrollIfDevelopable(V, F);
  ASSERT_TRUE(uv.has_value());
  Layout layout;
  layout.uv.resize(V.rows(), 2);
  for (int v = 0; v < V.rows(); ++v) layout.uv.row(v) = (*uv)[v].transpose();
  layout.face_uv = F;
  const StretchMetrics stretch = layoutStretch(V, F, layout);
  EXPECT_LT(stretch.linf, 1 + 1e-9);
  for (int f = 0; f < F.rows(); ++f)  // counter-clockwise, as the faces run
    EXPECT_GT(signedArea((*uv)[F(f, 0)], (*uv)[F(f, 1)], (*uv)[F(f, 2)]), 0);
  // A sphere's cap curves: nothing.
  const Mesh ball = sphere(2);
  std::vector<int> cap;
  for (int f = 0; f < ball.F.rows(); ++f)
    if (ball.V.row(ball.F(f, 0)).z() > 0.3 && ball.V.row(ball.F(f, 1)).z() > 0.3 &&
        ball.V.row(ball.F(f, 2)).z() > 0.3)
      cap.push_back(f);
  ASSERT_GT(cap.size(), 4u);
  Triangles capF(cap.size(), 3);
  for (size_t f = 0; f < cap.size(); ++f) capF.row(f) = ball.F.row(cap[f]);
  EXPECT_FALSE(unrollIfDevelopable(ball.V, capF).has_value());
}

TEST(Atlas, AHolesWallIsUnrolledExactlyInFewCharts) {
  // A plate's drilled hole: its wall is a ring, cut first into flat patches of 20 degrees (18
  // around). Each piece, and any arc of them, is developable and is unrolled exactly; merged
  // back their rectangles add up exactly (rounding had refused such merges, leaving 9 charts and
  // their seams on each wall).
  // Beside it a large square of its own, so that a wall unrolled whole is shorter than the
  // square root of the mesh's area (a longer chart is halved for packing), as in a plate.
  const Mesh mesh = withSquareBeside(thickTube(36, 2, 0.5, 1.0, 0.1), 8);
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
  for (int wall = 0; wall < 2; ++wall) {
    std::set<int> charts;
    for (int i = 0; i < 36; ++i)
      for (int k = 0; k < 4; ++k) {
        // Per step around: rows of (outer quad, inner quad), then the top and bottom quads.
        const int face = i * 12 + (wall == 1 ? 0 : 2) + 4 * (k / 2) + k % 2;
        charts.insert(r.layout.chart[face]);
      }
    EXPECT_LE(charts.size(), 3u) << (wall == 0 ? "inner" : "outer") << " wall";
  }
  int unrolled = 0;
  for (const ChartReport& chart : r.report.chart_table)
    if (chart.boundary_used == "developable unrolled") {
      ++unrolled;
      EXPECT_LT(chart.linf_stretch, 1 + 1e-9);
    }
  EXPECT_GE(unrolled, 2);
}

TEST(Atlas, AFlatFaceOfSliversIsProjectedWithoutStretch) {
  // A box whose faces are fans of needles (as CAD exporters triangulate flat faces): 40 points
  // along one edge of each side, fanned to the opposite corner. Every chart is a flat face laid
  // flat by projection, so no sliver stretches.
  const int n = 40;
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<int, 3>> f;
  const Eigen::Vector3d size(2, 1.5, 1);
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      // The side's corner frame: origin o, edges a (the fanned one) and b, outward normal a x b.
      Eigen::Vector3d o = Eigen::Vector3d::Zero(), a = Eigen::Vector3d::Zero(),
                      b = Eigen::Vector3d::Zero();
      const int i = (axis + 1) % 3, j = (axis + 2) % 3;
      a[i] = size[i], b[j] = size[j];
      if (side == 1) o[axis] = size[axis];
      if (side == 0) std::swap(a, b);  // the normal points out on both sides
      const int first = static_cast<int>(v.size());
      for (int k = 0; k <= n; ++k) v.push_back(o + a * k / n);
      v.push_back(o + a + b), v.push_back(o + b);
      for (int k = 0; k < n; ++k) f.push_back({first + k, first + k + 1, first + n + 1});
      f.push_back({first, first + n + 1, first + n + 2});
    }
  const Mesh mesh = meshOf(v, f);
  const AtlasOptions o = quickOptions();
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
  EXPECT_EQ(r.report.charts, 6);
  EXPECT_LT(r.report.linf_stretch, 1 + 1e-9);
  for (const ChartReport& chart : r.report.chart_table)
    EXPECT_EQ(chart.boundary_used, "planar projection");
}

TEST(Atlas, NeighbouringChartsMergeBackWithinTheChartLimits) {
  const Mesh mesh = torus(96, 32);  // cut first into parts no limit asked for
  AtlasOptions o = quickOptions();
  const AtlasResult merged = makeAtlas(mesh.V, mesh.F, o);
  o.merge_charts = false;
  const AtlasResult split = makeAtlas(mesh.V, mesh.F, o);
  o.merge_charts = true;
  expectCertified(mesh, merged, o);
  expectCertified(mesh, split, o);
  EXPECT_GT(merged.report.charts_merged, 0);
  EXPECT_EQ(split.report.charts_merged, 0);
  EXPECT_EQ(merged.report.charts, split.report.charts - merged.report.charts_merged);
  EXPECT_LT(merged.report.seam, split.report.seam);
  for (const ChartReport& chart : merged.report.chart_table) {
    EXPECT_LE(chart.l2_stretch, o.max_chart_stretch);
    if (chart.faces > 50) EXPECT_LE(chart.linf_stretch, 4.0);
  }
}

// The shared closed models, when they are beside the clone.
class ClosedMesh : public ::testing::TestWithParam<const char*> {};

TEST_P(ClosedMesh, CertifiedAsStoredWithLowStretch) {
  SDP_MESH_OR_SKIP(path, std::string("closed/") + GetParam());
  const io::MeshData data = io::readMesh(path);
  const Mesh mesh{data.V, data.F};
  AtlasOptions o;
  o.storage = UVStorage::FloatAndSixDecimals;
  const AtlasResult r = makeAtlas(mesh.V, mesh.F, o);
  expectCertified(mesh, r, o);
}

INSTANTIATE_TEST_SUITE_P(Shared, ClosedMesh,
                         ::testing::Values("decimated-knight.off", "bunny.off", "fertility.off",
                                           "horse_quad.obj", "truck.obj"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// The cells of an n x n grid of unit squares that `keep` holds, as a flat chart of two
// counter-clockwise triangles per cell (shared corners shared).
ChartShape gridChart(int n, const std::function<bool(int, int)>& keep) {
  ChartShape chart;
  std::map<std::pair<int, int>, int> index;
  auto corner = [&](int x, int y) {
    auto [it, added] = index.emplace(std::make_pair(x, y), static_cast<int>(chart.uv.size()));
    if (added) chart.uv.emplace_back(x, y);
    return it->second;
  };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      if (!keep(x, y)) continue;
      const int a = corner(x, y), b = corner(x + 1, y), c = corner(x + 1, y + 1),
                d = corner(x, y + 1);
      chart.triangles.push_back({a, b, c});
      chart.triangles.push_back({a, c, d});
    }
  return chart;
}

TEST(AtlasConvexCut, BoundaryLoopIsOneLoopOrNothing) {
  const ChartShape square = gridChart(4, [](int, int) { return true; });
  const std::vector<int> loop = boundaryLoop(square.triangles);
  ASSERT_EQ(loop.size(), 16u);  // the 16 grid corners on the square's sides, in order
  for (size_t i = 0; i < loop.size(); ++i)
    EXPECT_NEAR((square.uv[loop[i]] - square.uv[loop[(i + 1) % loop.size()]]).norm(), 1.0, 1e-12);
  // Two cells touching at one corner: the boundary passes that corner twice, not one loop.
  const ChartShape pinched = gridChart(2, [](int x, int y) { return x == y; });
  EXPECT_TRUE(boundaryLoop(pinched.triangles).empty());
}

TEST(AtlasConvexCut, AnLShapeIsCutAcrossItsArmAConvexChartIsNot) {
  // A 20 x 20 square without its 14 x 14 top right: two arms 6 wide meeting in a corner.
  const ChartShape l_shape = gridChart(20, [](int x, int y) { return x < 6 || y < 6; });
  const std::optional<ConvexCut> cut = bestConvexCut(l_shape.uv, l_shape.triangles, 0.05);
  ASSERT_TRUE(cut.has_value());
  // The hull (400 - 14^2 / 2 = 302) against the L's area (204): a cut where an arm meets the
  // corner square leaves two rectangles, whose hulls are their areas; the offsets tried are
  // 32nds of the width, so the cut falls within 0.625 of that.
  EXPECT_GT(cut->hull_gain, 0.95 * (302 - 204));
  EXPECT_LE(cut->hull_gain, 302 - 204 + 1e-9);
  EXPECT_NEAR(cut->length, 6, 1e-9);  // across an arm, not along it
  EXPECT_NEAR(std::abs(cut->normal.x()) + std::abs(cut->normal.y()), 1, 1e-9);  // axis-aligned

  const ChartShape square = gridChart(10, [](int, int) { return true; });
  EXPECT_FALSE(bestConvexCut(square.uv, square.triangles, 0.05).has_value());
  // A long rectangle has no cut that removes hull area; the middle cut halves its length.
  const ChartShape strip = gridChart(20, [](int, int y) { return y < 2; });
  double extent = 0;
  const ConvexCut middle = middleCut(strip.uv, extent);
  EXPECT_NEAR(extent, 20, 1e-9);
  EXPECT_NEAR(std::abs(middle.normal.x()), 1, 1e-9);
  EXPECT_NEAR(middle.offset * middle.normal.x(), 10, 1e-9);
}

// The charts placed by the packing, as one layout (each chart its own rows, faces in chart
// order) for the pixel checks.
Layout packedLayout(const std::vector<ChartShape>& charts, const Packing& packing, int size) {
  Layout layout;
  int rows = 0, faces = 0;
  for (const ChartShape& c : charts) rows += c.uv.size(), faces += c.triangles.size();
  layout.uv.resize(rows, 2);
  layout.face_uv.resize(faces, 3);
  layout.chart.resize(faces);
  for (int c = 0, row = 0, f = 0; c < static_cast<int>(charts.size()); ++c) {
    for (size_t v = 0; v < charts[c].uv.size(); ++v)
      layout.uv.row(row + v) = packing.apply(c, charts[c].uv[v], size).transpose();
    for (const auto& t : charts[c].triangles) {
      layout.face_uv.row(f) << row + t[0], row + t[1], row + t[2];
      layout.chart[f++] = c;
    }
    row += charts[c].uv.size();
  }
  return layout;
}

// The packed charts as stored: inside the unit square, no pixel covered twice, every gutter
// kept, checked pixel by pixel at the texture size.
void expectPackedCleanly(const std::vector<ChartShape>& charts, const Packing& packing, int size,
                         int gutter) {
  const Layout layout = packedLayout(charts, packing, size);
  EXPECT_LE(layout.uv.maxCoeff(), 1.0);
  EXPECT_GE(layout.uv.minCoeff(), 0.0);
  const PixelMeasures pixels = measurePixels(layout, layout.chart, size, gutter);
  EXPECT_EQ(pixels.overlapping_pixels, 0);
  EXPECT_EQ(pixels.gutter_violations, 0);
}

TEST(AtlasPack, ConcaveChartsInterlockWithoutOverlapOrGutterBreach) {
  // Twelve L-shaped charts and forty small squares (each footprint rastered from the chart's
  // border and the column lines inside it), packed and checked pixel by pixel at several gutters.
  std::vector<ChartShape> charts;
  for (int i = 0; i < 12; ++i)
    charts.push_back(gridChart(8 + i % 4, [&](int x, int y) { return x < 3 || y < 2 + i % 3; }));
  // And small squares, which would drop into a large chart's inside if its footprint missed it.
  for (int i = 0; i < 40; ++i) charts.push_back(gridChart(1, [](int, int) { return true; }));
  // Corners off the grid (each moved by up to 0.2 cell): with every corner on a lattice, pixel
  // centres fall on shared corners, where the stored checks' rounding is not this test's subject.
  for (ChartShape& chart : charts)
    for (size_t v = 0; v < chart.uv.size(); ++v)
      chart.uv[v] += 0.2 * Eigen::Vector2d(std::sin(12.9898 * v), std::cos(78.233 * v));
  for (int gutter : {1, 2, 4}) {
    PackOptions options;
    options.texture_size = 512;
    options.gutter = gutter;
    SCOPED_TRACE(gutter);
    const Packing packing = packCharts(charts, options);
    expectPackedCleanly(charts, packing, 512, gutter);
    double area = 0;
    for (const ChartShape& c : charts) area += uvArea(c.uv, c.triangles);
    // The L's interlock: more of the square is used than their bounding boxes would allow.
    EXPECT_GT(area * packing.texels_per_unit * packing.texels_per_unit / (512.0 * 512.0), 0.5)
        << gutter;
  }
}

TEST(AtlasPack, AChartsHoleStaysFreeForAnother) {
  // A 10 x 10 frame around a 4 x 4 hole, and a 2 x 2 square: at the largest scale the frame
  // spans the texture, so the square fits only inside the hole, and does (the frame's footprint
  // comes from all its border edges, the hole's loop too, even-odd per column).
  ChartShape frame = gridChart(10, [](int x, int y) { return x < 3 || x >= 7 || y < 3 || y >= 7; });
  ASSERT_TRUE(boundaryLoop(frame.triangles).empty());  // two loops
  EXPECT_EQ(borderEdges(frame.triangles).size(), 40u + 16u);
  std::vector<ChartShape> charts = {frame, gridChart(2, [](int, int) { return true; })};
  PackOptions options;
  options.texture_size = 256;
  const Packing packing = packCharts(charts, options);
  // Beside the frame the two would need 12 units across; inside, 10 and the gutter.
  EXPECT_GT(packing.texels_per_unit * 10, 0.95 * 256);
  const Eigen::Vector2d square_centre = packing.apply(1, Eigen::Vector2d(1, 1), 256);
  const Eigen::Vector2d hole_centre = packing.apply(0, Eigen::Vector2d(5, 5), 256);
  EXPECT_LT((square_centre - hole_centre).cwiseAbs().maxCoeff() * 256,
            packing.texels_per_unit * 1.0 + 1);
  expectPackedCleanly(charts, packing, 256, options.gutter);
}

TEST(AtlasPack, AStripTooLongForTheTextureGoesAcrossItsDiagonal) {
  // A strip of two triangles, 40 by 1: along the texture's side it would fit at 254 / 40 texels a
  // unit; across the diagonal at up to sqrt(2) times that. Then it and a few squares beside it
  // are checked pixel by pixel.
  std::vector<ChartShape> charts;
  charts.push_back({{{0, 0}, {40, 0}, {40, 1}, {0, 1}}, {{0, 1, 2}, {0, 2, 3}}});
  for (int i = 0; i < 6; ++i) charts.push_back(gridChart(1, [](int, int) { return true; }));
  PackOptions options;
  options.texture_size = 256;
  const Packing packing = packCharts(charts, options);
  EXPECT_GT(packing.texels_per_unit, 1.3 * 254 / 40);
  const Eigen::Vector2d along = packing.placements[0].rotation * Eigen::Vector2d(1, 0);
  EXPECT_NEAR(std::abs(along.x()), std::abs(along.y()), 1e-9);  // at 45 degrees
  expectPackedCleanly(charts, packing, 256, options.gutter);
}

// The unit square's (n + 1)^2 grid, each cell cut by the same diagonal, lifted to
// height(u, v) (called once per vertex, row by row).
Mesh gridSheet(int n, const std::function<double(double, double)>& height) {
  Mesh mesh;
  mesh.V.resize((n + 1) * (n + 1), 3);
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) {
      const double u = double(x) / n, v = double(y) / n;
      mesh.V.row(y * (n + 1) + x) << u, v, height(u, v);
    }
  mesh.F.resize(2 * n * n, 3);
  for (int y = 0, f = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = y * (n + 1) + x, b = a + 1, c = a + n + 2, d = a + n + 1;
      mesh.F.row(f++) << a, b, c;
      mesh.F.row(f++) << a, c, d;
    }
  return mesh;
}

// The 3D length of the edges between faces of different parts.
double cutLength(const Mesh& mesh, const Connectivity& connectivity,
                 const std::vector<std::vector<int>>& parts) {
  std::vector<int> part(mesh.F.rows(), -1);
  for (size_t p = 0; p < parts.size(); ++p)
    for (int f : parts[p]) part[f] = static_cast<int>(p);
  double cut = 0;
  for (int h = 0; h < 3 * static_cast<int>(mesh.F.rows()); ++h) {
    const int t = connectivity.twin[h];
    if (t > h && part[h / 3] != part[t / 3])
      cut += (mesh.V.row(mesh.F(h / 3, h % 3)) - mesh.V.row(mesh.F(h / 3, (h % 3 + 1) % 3))).norm();
  }
  return cut;
}

TEST(AtlasCharts, SplitBorderIsStraightenedNotAZigZag) {
  // A flat square grid, each cell cut by the same diagonal: two parts grown from far seeds meet
  // along a staircase of grid edges unless the border is straightened (ears moved across).
  const Mesh mesh = gridSheet(24, [](double, double) { return 0.0; });
  const Connectivity connectivity = analyzeConnectivity(mesh.F, static_cast<int>(mesh.V.rows()));
  const FaceGraph graph = buildFaceGraph(mesh.V, mesh.F, connectivity);
  std::vector<int> faces(mesh.F.rows());
  std::iota(faces.begin(), faces.end(), 0);
  FaceScratch scratch(graph);
  const auto parts = splitFaces(graph, faces, 2, scratch);
  ASSERT_EQ(parts.size(), 2u);
  for (int p = 0; p < 2; ++p) EXPECT_TRUE(regionIsDisk(graph, parts[p], scratch));
  const double cut = cutLength(mesh, connectivity, parts);
  // The parts meet across the square: a straight cut there is 1 long; the border as grown is a
  // zig-zag about 15 % longer (1.15 here before the ears are moved, 1.03 after).
  EXPECT_LT(cut, 1.08) << cut;
}

TEST(AtlasCharts, NoiseOnSingleFacesDoesNotRagThePartsBorders) {
  // A gently curved sheet, and its twin with scanner-like noise (each vertex moved up or down by
  // 0.15 mean edge lengths, Gaussian): split into the same number of parts, the noisy twin's
  // parts meet along borders about as long as the clean sheet's (1.02 times here). Grown by
  // the faces' own normals, which the noise tilts by tens of degrees, they were 1.25 times as
  // long (charts.cpp: the growth normals are smoothed).
  const int n = 120;
  auto partsAndCut = [&](double sigma) {
    sdp::test::SplitMix64 random(7);
    MeshGraph m(gridSheet(n, [&](double u, double v) {
      return 0.1 * std::sin(3 * u) * std::cos(2 * v) + sigma / n * random.normal();
    }));
    const auto parts = splitFaces(m.graph, m.faces, 16, m.scratch);
    return std::make_pair(parts.size(), cutLength(m.mesh, m.connectivity, parts));
  };
  const auto [clean_parts, clean_cut] = partsAndCut(0);
  const auto [noisy_parts, noisy_cut] = partsAndCut(0.15);
  EXPECT_EQ(noisy_parts, clean_parts);
  EXPECT_LT(noisy_cut, 1.1 * clean_cut) << noisy_cut << " against " << clean_cut;
}

TEST(AtlasCharts, LargeSplitGrownInHalvesCoversEveryFaceOnceWithDisks) {
  // Over 200k faces the parts grow in two halves at once (charts.cpp): every face still in one
  // part, every part a disk, the scratch left as found, and the same parts on a second run.
  const Mesh mesh =
      gridSheet(320, [](double u, double v) { return 0.1 * std::sin(6 * u) * std::cos(4 * v); });
  ASSERT_GE(mesh.F.rows(), 200000);
  const Connectivity connectivity = analyzeConnectivity(mesh.F, static_cast<int>(mesh.V.rows()));
  const FaceGraph graph = buildFaceGraph(mesh.V, mesh.F, connectivity);
  std::vector<int> faces(mesh.F.rows());
  std::iota(faces.begin(), faces.end(), 0);
  FaceScratch scratch(graph);
  const auto parts = splitFaces(graph, faces, 600, scratch);
  EXPECT_GE(parts.size(), 400u);  // grid seeds: about one per part
  std::vector<int> times(faces.size(), 0);
  for (const auto& part : parts) {
    ASSERT_FALSE(part.empty());
    EXPECT_TRUE(regionIsDisk(graph, part, scratch));
    for (int f : part) ++times[f];
  }
  EXPECT_EQ(std::count(times.begin(), times.end(), 1), static_cast<long>(faces.size()));
  EXPECT_EQ(std::count(scratch.region.begin(), scratch.region.end(), kOutside),
            static_cast<long>(faces.size()));
  EXPECT_EQ(splitFaces(graph, faces, 600, scratch), parts);
}

}  // namespace
}  // namespace sdp::atlas
