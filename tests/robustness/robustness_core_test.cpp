// Robustness of the core entry point sdp::parameterize (tests/robustness/CASES.md): the cases of
// the robustness issue that tests/core does not cover yet, and allocation failures injected at
// every allocation of a run (the "mesh too large for memory" case without needing a large mesh).
//
// Contract checked everywhere: either a Result whose map is one-to-one (every face has positive
// signed UV area, counted here independently of the core's metrics), or a ParameterizationError
// whose message is one line. Nothing else may leave parameterize(): no std::bad_alloc, no other
// exception, no abort.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <random>
#include <string>
#include <typeinfo>
#include <vector>

#include "core/parameterize.h"
#include "io/mesh_io.h"
#include "test_mesh_files.h"
#include "test_meshes.h"  // tests/core: grids, fans, countNonPositiveFaces

// --- allocation failure injection ----------------------------------------------------------------
// Every operator new of this program goes through allocate(). While armed, the allocation with
// index `fail_index` (counted over all threads from the arming on) throws std::bad_alloc, and so
// does every allocation of at least `fail_size` bytes. Only operator new is replaced: Eigen's
// own buffers (malloc) and OpenMP's runtime are left alone, so the failures land where the
// library's C++ code can see them.
namespace inject {
std::atomic<bool> armed{false};
std::atomic<long> seen{0};
std::atomic<long> fail_index{-1};
std::atomic<size_t> fail_size{static_cast<size_t>(-1)};
std::atomic<long> failures{0};

void* allocate(size_t n, size_t alignment = 0) {
  if (armed.load(std::memory_order_relaxed)) {
    const long k = seen.fetch_add(1, std::memory_order_relaxed) + 1;
    if (k == fail_index.load(std::memory_order_relaxed) ||
        n >= fail_size.load(std::memory_order_relaxed)) {
      failures.fetch_add(1, std::memory_order_relaxed);
      throw std::bad_alloc();
    }
  }
  if (n == 0) n = 1;
  void* p = nullptr;
  if (alignment > alignof(std::max_align_t)) {
    if (posix_memalign(&p, alignment, n) != 0) p = nullptr;
  } else {
    p = std::malloc(n);
  }
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

// Runs f with injection armed; returns with it disarmed whatever f does.
template <class F>
void armedRun(long index, size_t size, F&& f) {
  seen = 0;
  failures = 0;
  fail_index = index;
  fail_size = size;
  armed = true;
  try {
    f();
  } catch (...) {
    armed = false;
    throw;
  }
  armed = false;
}
}  // namespace inject

void* operator new(size_t n) {
  return inject::allocate(n);
}
void* operator new[](size_t n) {
  return inject::allocate(n);
}
void* operator new(size_t n, std::align_val_t a) {
  return inject::allocate(n, static_cast<size_t>(a));
}
void* operator new[](size_t n, std::align_val_t a) {
  return inject::allocate(n, static_cast<size_t>(a));
}
void* operator new(size_t n, const std::nothrow_t&) noexcept {
  try {
    return inject::allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](size_t n, const std::nothrow_t&) noexcept {
  try {
    return inject::allocate(n);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, size_t, std::align_val_t) noexcept {
  std::free(p);
}

namespace sdp {
namespace {

using test::countNonPositiveFaces;
using test::Mesh;

Options with(WeightScheme w, BoundaryShape b) {
  Options o;
  o.weights = w;
  o.boundary = b;
  return o;
}

constexpr WeightScheme kAllWeights[] = {WeightScheme::Straightest, WeightScheme::Ltd,
                                        WeightScheme::Floater, WeightScheme::MeanValue,
                                        WeightScheme::Uniform};
constexpr BoundaryShape kAllBoundaries[] = {BoundaryShape::Measured, BoundaryShape::Circle,
                                            BoundaryShape::Square};

// The reason parameterize() gives, or "" when it succeeds (then the map must be one-to-one).
std::string reasonFor(const Positions& V, const Triangles& F, const Options& o = {}) {
  try {
    const Result r = parameterize(V, F, o);
    EXPECT_EQ(countNonPositiveFaces(r, F), 0) << "a folded map was returned";
    EXPECT_EQ(r.report.flipped_faces, 0);
    return "";
  } catch (const ParameterizationError& e) {
    const std::string reason = e.what();
    EXPECT_EQ(reason.find('\n'), std::string::npos) << "not one line: " << reason;
    EXPECT_FALSE(reason.empty());
    return reason;
  }
}

Mesh wavyGrid(int n) {
  return test::grid(n, 1, 1, [](double x, double y) { return 0.3 * std::sin(3 * x + 2 * y); });
}

int gridIndex(int n, int i, int j) {
  return j * (n + 1) + i;
}

Mesh withoutFaces(const Mesh& m, std::vector<int> drop) {
  std::sort(drop.begin(), drop.end());
  Mesh out;
  out.V = m.V;
  out.F.resize(m.F.rows() - static_cast<Eigen::Index>(drop.size()), 3);
  int row = 0;
  for (int f = 0; f < m.F.rows(); ++f)
    if (!std::binary_search(drop.begin(), drop.end(), f)) out.F.row(row++) = m.F.row(f);
  return out;
}

Mesh withExtraFace(const Mesh& m, int a, int b, int c) {
  Mesh out{m.V, Triangles(m.F.rows() + 1, 3)};
  out.F.topRows(m.F.rows()) = m.F;
  out.F.row(m.F.rows()) << a, b, c;
  return out;
}

// --- topology and coordinates ----------------------------------------------------------------

TEST(CoreRobustness, InfiniteCoordinatesAreRefusedLikeNaN) {
  for (double bad : {std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity(), std::nan("")}) {
    Mesh m = wavyGrid(6);
    m.V(gridIndex(6, 3, 3), 1) = bad;
    EXPECT_EQ(reasonFor(m.V, m.F), "vertex 24 has a non-finite coordinate (NaN or infinity)")
        << bad;
  }
}

// The map comes back in the mesh's units (UV area = 3D area), so a mesh whose areas would leave
// the double range is refused; found by fuzzing: one coordinate mutated to 0.530e291 gave
// infinite UV areas.
TEST(CoreRobustness, MeshesBeyondTheDoubleRangeOfAreasAreRefused) {
  Mesh outlier = wavyGrid(6);
  outlier.V(gridIndex(6, 3, 3), 2) = 0.530e291;
  EXPECT_EQ(reasonFor(outlier.V, outlier.F),
            "the mesh spans 5.3e+290 units; 1e-100 to 1e100 are supported (areas in its units "
            "would leave the double range)");
  const Mesh m = wavyGrid(6);
  const Positions tiny = m.V * 1e-200;
  EXPECT_NE(reasonFor(tiny, m.F).find("the mesh spans 1e-200 units"), std::string::npos);
}

TEST(CoreRobustness, PinchedVertexIsNamed) {
  // Two non-adjacent faces of interior vertex (2, 2) removed: its faces form two fans, while the
  // mesh stays one piece through edges.
  const int n = 4, v = gridIndex(n, 2, 2);
  const Mesh m = test::grid(n, 1, 1, [](double, double) { return 0.0; });
  std::vector<int> ring;
  for (int f = 0; f < m.F.rows(); ++f)
    if (m.F(f, 0) == v || m.F(f, 1) == v || m.F(f, 2) == v) ring.push_back(f);
  const Eigen::RowVector3d centre = m.V.row(v);
  std::sort(ring.begin(), ring.end(), [&](int a, int b) {
    auto angle = [&](int f) {
      const Eigen::RowVector3d c =
          (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))) / 3.0 - centre;
      return std::atan2(c.y(), c.x());
    };
    return angle(a) < angle(b);
  });
  ASSERT_EQ(ring.size(), 8u);
  const Mesh pinched = withoutFaces(m, {ring[0], ring[4]});
  EXPECT_EQ(reasonFor(pinched.V, pinched.F),
            "vertex 12 is non-manifold (two parts of the surface meet only at this vertex)");
}

TEST(CoreRobustness, DuplicateFacesInEitherOrientationAreRefused) {
  const Mesh m = wavyGrid(4);
  const auto f = m.F.row(9);
  // Same orientation (also rotated): named as duplicates.
  Mesh same = withExtraFace(m, f(1), f(2), f(0));
  EXPECT_EQ(reasonFor(same.V, same.F), "faces 9 and 32 are duplicates");
  // Opposite orientation: a third face on each of its edges, named as a non-manifold edge.
  Mesh reversed = withExtraFace(m, f(0), f(2), f(1));
  EXPECT_NE(reasonFor(reversed.V, reversed.F).find("(a non-manifold edge)"), std::string::npos);
  // A lone triangle and its reverse: a closed two-sided surface.
  Positions V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  Triangles F(2, 3);
  F << 0, 1, 2, 0, 2, 1;
  EXPECT_NE(reasonFor(V, F).find("closed"), std::string::npos);
}

TEST(CoreRobustness, TriangleSoupIsRefusedAsManyComponents) {
  // STL-like: every face has its own three vertices (duplicate vertices, never merged).
  const Mesh grid = wavyGrid(3);
  Mesh soup{Positions(3 * grid.F.rows(), 3), Triangles(grid.F.rows(), 3)};
  for (int f = 0; f < grid.F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      soup.V.row(3 * f + c) = grid.V.row(grid.F(f, c));
      soup.F(f, c) = 3 * f + c;
    }
  EXPECT_EQ(reasonFor(soup.V, soup.F),
            "the mesh has 18 connected components: its faces share no edges (merge duplicate "
            "vertices first)");
}

// Vertices duplicated along a cut from the boundary into the middle (a scan stitched from two
// pieces): by connectivity the patch is still a disk with a slit, and it is flattened as one,
// the two sides of the slit getting separate UVs.
TEST(CoreRobustness, DuplicateVerticesAlongACutGiveASlitThatOpensUp) {
  const int n = 8, row = n / 2;
  const Mesh m = wavyGrid(n);
  std::vector<int> copy_of(m.V.rows(), -1);
  Positions V(m.V.rows() + row, 3);
  V.topRows(m.V.rows()) = m.V;
  for (int i = 0; i < row; ++i) {  // the tip (i == row) stays one vertex
    copy_of[gridIndex(n, i, row)] = static_cast<int>(m.V.rows()) + i;
    V.row(m.V.rows() + i) = m.V.row(gridIndex(n, i, row));
  }
  Triangles F = m.F;
  for (int f = 0; f < F.rows(); ++f) {
    const double cy = (m.V(F(f, 0), 1) + m.V(F(f, 1), 1) + m.V(F(f, 2), 1)) / 3;
    if (cy > 0.5)
      for (int c = 0; c < 3; ++c)
        if (copy_of[F(f, c)] >= 0) F(f, c) = copy_of[F(f, c)];
  }
  for (BoundaryShape b : kAllBoundaries) {
    const Result r = parameterize(V, F, with(WeightScheme::Straightest, b));
    EXPECT_EQ(countNonPositiveFaces(r, F), 0) << boundaryShapeName(b);
    EXPECT_EQ(r.report.holes_filled, 0);
    for (int i = 1; i < row; ++i) {  // interior slit vertices: both sides apart
      const int a = gridIndex(n, i, row), c = copy_of[a];
      EXPECT_GT((r.layout.uv.row(a) - r.layout.uv.row(c)).norm(), 1e-6) << "slit vertex " << a;
    }
  }
}

TEST(CoreRobustness, UnreferencedVerticesAreIgnoredEvenWhenNotFinite) {
  const Mesh m = wavyGrid(6);
  Positions V(m.V.rows() + 3, 3);
  V << m.V, Eigen::RowVector3d(7, 7, 7), Eigen::RowVector3d(std::nan(""), 0, 0),
      Eigen::RowVector3d(std::numeric_limits<double>::infinity(), 0, 0);
  const Result base = parameterize(m.V, m.F);
  const Result r = parameterize(V, m.F);
  EXPECT_EQ(r.layout.uv.rows(), V.rows());
  EXPECT_EQ(r.report.unreferenced_vertices, 3);
  EXPECT_EQ(r.report.vertices, m.V.rows());
  for (int v = static_cast<int>(m.V.rows()); v < V.rows(); ++v)
    EXPECT_EQ(r.layout.uv.row(v), Eigen::RowVector2d(0, 0));
  EXPECT_LT((r.layout.uv.topRows(m.V.rows()) - base.layout.uv).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(countNonPositiveFaces(r, m.F), 0);
}

TEST(CoreRobustness, SourceVertexReasons) {
  Mesh m = wavyGrid(6);
  Positions V(m.V.rows() + 1, 3);
  V << m.V, Eigen::RowVector3d(9, 9, 9);  // vertex 49: in range, used by no face
  Options o;
  o.source_vertex = 49;
  EXPECT_EQ(reasonFor(V, m.F, o), "source vertex 49 is not used by any face");
  o.source_vertex = 50;
  EXPECT_EQ(reasonFor(V, m.F, o), "source vertex 50 is out of range (the mesh has 50 vertices)");
  o.source_vertex = 3;  // on the bottom edge
  EXPECT_EQ(reasonFor(V, m.F, o),
            "source vertex 3 is on the boundary; the measured boundary needs an interior vertex");
  // Circle and square do not use S: a boundary source is accepted and not reported.
  for (BoundaryShape b : {BoundaryShape::Circle, BoundaryShape::Square}) {
    Options shaped = with(WeightScheme::Straightest, b);
    shaped.source_vertex = 3;
    const Result r = parameterize(m.V, m.F, shaped);
    EXPECT_EQ(r.report.source_vertex, -1);
    EXPECT_EQ(countNonPositiveFaces(r, m.F), 0);
  }
}

// Without interior vertices the measured boundary has no source: the circle is used and said.
TEST(CoreRobustness, NoInteriorVertexForEveryWeightAndBoundary) {
  // A strip one cell high and five long: every vertex on the boundary.
  Mesh thin;
  thin.V.resize(12, 3);
  thin.F.resize(10, 3);
  for (int i = 0; i <= 5; ++i) {
    thin.V.row(i) << i, 0, 0.1 * i * i;
    thin.V.row(6 + i) << i, 1, 0.1 * i * i;
  }
  for (int i = 0; i < 5; ++i) {
    thin.F.row(2 * i) << i, i + 1, 7 + i;
    thin.F.row(2 * i + 1) << i, 7 + i, 6 + i;
  }
  for (WeightScheme w : kAllWeights)
    for (BoundaryShape b : kAllBoundaries) {
      const Result r = parameterize(thin.V, thin.F, with(w, b));
      EXPECT_EQ(countNonPositiveFaces(r, thin.F), 0);
      if (b == BoundaryShape::Measured) {
        EXPECT_EQ(r.report.boundary_used, "circle");
        ASSERT_FALSE(r.report.warnings.empty());
        EXPECT_EQ(r.report.warnings[0],
                  "the patch has no interior vertex to measure the boundary from; used the "
                  "circle boundary instead");
      }
    }
  Options o;
  o.source_vertex = 2;  // every vertex is on the boundary
  EXPECT_NE(reasonFor(thin.V, thin.F, o).find("is on the boundary"), std::string::npos);
}

TEST(CoreRobustness, OneTriangleForEveryWeightAndBoundary) {
  Positions V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 0.2, 0.9, 0.3;
  Triangles F(1, 3);
  F << 0, 1, 2;
  for (WeightScheme w : kAllWeights)
    for (BoundaryShape b : kAllBoundaries) {
      const Result r = parameterize(V, F, with(w, b));
      EXPECT_EQ(countNonPositiveFaces(r, F), 0);
      EXPECT_TRUE(std::isfinite(r.report.l2_stretch));
    }
}

// Needles with non-zero area (aspect ratio ~1e4) and a 1e-7 short edge: a one-to-one map for
// every scheme and boundary.
TEST(CoreRobustness, NeedleTrianglesForEveryWeightAndBoundary) {
  const int n = 12;
  Mesh needles = test::grid(n, 1, 1, [](double x, double y) { return 0.1 * x * y; });
  for (int j = 0; j <= n; ++j) needles.V(gridIndex(n, 6, j), 0) = 5.0 / n + 1e-5;
  Mesh short_edge = wavyGrid(8);
  const int v = gridIndex(8, 4, 4), w = gridIndex(8, 5, 4);
  short_edge.V.row(v) =
      short_edge.V.row(v) + (1 - 1e-7) * (short_edge.V.row(w) - short_edge.V.row(v));
  for (const Mesh* m : {&needles, &short_edge})
    for (WeightScheme scheme : kAllWeights)
      for (BoundaryShape b : kAllBoundaries) {
        const Result r = parameterize(m->V, m->F, with(scheme, b));
        EXPECT_EQ(countNonPositiveFaces(r, m->F), 0)
            << weightSchemeName(scheme) << " " << boundaryShapeName(b);
      }
}

// Every vertex at one point or on one line: no 3D area at all. The result is the connectivity's
// Tutte map (uniform weights on the circle), flagged by the degenerate-ring fallback, with the
// stretch not finite; never NaN UVs.
TEST(CoreRobustness, GeometryWithoutAreaGivesAConnectivityMapAndSaysSo) {
  Mesh point = test::planarGrid(4);
  point.V.rowwise() = Eigen::RowVector3d(0.3, 0.3, 0.3);
  Mesh line = test::planarGrid(4);
  line.V.col(1).setZero();
  for (const Mesh* m : {&point, &line})
    for (BoundaryShape b : kAllBoundaries) {
      const Result r = parameterize(m->V, m->F, with(WeightScheme::Straightest, b));
      EXPECT_TRUE(r.layout.uv.allFinite());
      EXPECT_EQ(countNonPositiveFaces(r, m->F), 0);
      EXPECT_GT(r.report.fallbacks[Fallback::DegenerateRing], 0);
      EXPECT_FALSE(r.report.warnings.empty());
    }
}

// Holes are filled virtually: a map of the real faces for every scheme and boundary, UVs only
// for the input vertices.
TEST(CoreRobustness, HolesForEveryWeightAndBoundary) {
  const int n = 8;
  const Mesh m = wavyGrid(n);
  const Mesh two_holes =
      withoutFaces(m, {2 * (2 * n + 2), 2 * (2 * n + 2) + 1, 2 * (5 * n + 5), 2 * (5 * n + 5) + 1});
  for (WeightScheme w : kAllWeights)
    for (BoundaryShape b : kAllBoundaries) {
      const Result r = parameterize(two_holes.V, two_holes.F, with(w, b));
      EXPECT_EQ(r.report.holes_filled, 2);
      EXPECT_EQ(r.layout.uv.rows(), m.V.rows());
      EXPECT_EQ(r.face_stretch.size(), static_cast<size_t>(two_holes.F.rows()));
      EXPECT_EQ(countNonPositiveFaces(r, two_holes.F), 0)
          << weightSchemeName(w) << " " << boundaryShapeName(b);
    }
}

// uv ~ s * base + t: the largest residual after the best scale s and offset t, relative to the
// spread of the base map.
double similarityResidual(const UVs& base, const UVs& uv) {
  const Eigen::RowVector2d mb = base.colwise().mean(), mu = uv.colwise().mean();
  const UVs b = base.rowwise() - mb, u = uv.rowwise() - mu;
  const double s = (b.array() * u.array()).sum() / b.squaredNorm();
  const double spread = std::sqrt(b.squaredNorm() / static_cast<double>(b.rows()));
  return (u - s * b).cwiseAbs().maxCoeff() / (std::abs(s) * spread);
}

// The real Nefertiti patch far from the origin or scaled: the same map up to scale, for every
// boundary.
TEST(CoreRobustness, NefertitiMapIsScaleAndTranslationInvariant) {
  SDP_MESH_OR_SKIP(path, "disk/nefertiti.off");
  const io::MeshData mesh = io::readMesh(path);
  const double cases[][2] = {{1e-6, 0}, {1e6, 0}, {1, 1e6}, {1, -1e6}, {1e-3, 1e3}};
  for (BoundaryShape b : kAllBoundaries) {
    const Options o = with(WeightScheme::Straightest, b);
    const Result base = parameterize(mesh.V, mesh.F, o);
    for (const auto& c : cases) {
      Positions V = mesh.V * c[0];
      V.array() += c[1];
      const Result r = parameterize(V, mesh.F, o);
      SCOPED_TRACE(std::string(boundaryShapeName(b)) + " scale " + std::to_string(c[0]) +
                   " offset " + std::to_string(c[1]));
      EXPECT_EQ(countNonPositiveFaces(r, mesh.F), 0);
      EXPECT_EQ(r.report.source_vertex, base.report.source_vertex);
      EXPECT_EQ(r.report.boundary_used, base.report.boundary_used);
      EXPECT_NEAR(r.report.l2_stretch, base.report.l2_stretch, 1e-6 * base.report.l2_stretch);
      EXPECT_NEAR(r.report.linf_stretch, base.report.linf_stretch, 1e-5 * base.report.linf_stretch);
      EXPECT_LT(similarityResidual(base.layout.uv, r.layout.uv), 1e-6);
    }
  }
}

// Far outside 1e-6..1e6, the same map: the core computes in coordinates scaled to unit size,
// up to the supported 1e-100..1e100 (see CASES.md).
TEST(CoreRobustness, ExtremeScalesGiveTheSameMap) {
  const Mesh m = wavyGrid(8);
  const Result base = parameterize(m.V, m.F);
  for (double scale : {1e-90, 1e90, 1e-50, 1e50, 1e-30, 1e30}) {
    SCOPED_TRACE("scale 1e" + std::to_string(static_cast<int>(std::log10(scale))));
    const Positions V = m.V * scale;
    const Result r = parameterize(V, m.F);
    EXPECT_EQ(countNonPositiveFaces(r, m.F), 0);
    EXPECT_EQ(r.report.fallbacks.total(), 0);
    EXPECT_NEAR(r.report.l2_stretch, base.report.l2_stretch, 1e-9);
    EXPECT_LT(similarityResidual(base.layout.uv, r.layout.uv), 1e-6);
  }
}

// A map that comes out folded is never returned: interior vertices of a curved grid thrown far
// out of place (non-star-shaped rings, faces folded over in 3D). Each run either returns a
// one-to-one map or refuses with a one-line reason.
TEST(CoreRobustness, WildlyDisplacedVerticesNeverGiveAFoldedMap) {
  std::mt19937 random(12345);
  std::normal_distribution<double> jump(0.0, 0.4);
  const int n = 10;
  int returned = 0, refused = 0;
  for (int trial = 0; trial < 60; ++trial) {
    Mesh m = wavyGrid(n);
    for (int k = 0; k < 1 + trial % 6; ++k) {
      const int i = 1 + static_cast<int>(random() % (n - 1)),
                j = 1 + static_cast<int>(random() % (n - 1));
      m.V.row(gridIndex(n, i, j)) += Eigen::RowVector3d(jump(random), jump(random), jump(random));
    }
    const Options o = with(kAllWeights[trial % 5], kAllBoundaries[trial % 3]);
    const std::string reason = reasonFor(m.V, m.F, o);
    (reason.empty() ? returned : refused) += 1;
  }
  EXPECT_GT(returned, 0);
  RecordProperty("returned", returned);
  RecordProperty("refused", refused);
}

// --- allocation failures ---------------------------------------------------------------------

constexpr size_t kNoSize = static_cast<size_t>(-1);  // no size limit

struct InjectionOutcome {
  int succeeded = 0, refused = 0;
  std::vector<std::string> problems;  // anything but success or a one-line memory reason
};

// Runs parameterize once with the allocation `index` (1-based) failing, or every allocation of
// at least `size` bytes failing, and classifies what came out.
void runInjected(const Mesh& m, const Options& o, long index, size_t size, InjectionOutcome& out) {
  std::string problem;
  bool ok = false;
  try {
    Result r;
    inject::armedRun(index, size, [&] { r = parameterize(m.V, m.F, o); });
    ok = true;
    if (countNonPositiveFaces(r, m.F) != 0) problem = "a folded map was returned";
  } catch (const ParameterizationError& e) {
    const std::string reason = e.what();
    if (reason.find("memory") == std::string::npos || reason.find('\n') != std::string::npos)
      problem = "ParameterizationError without a memory reason: " + reason;
  } catch (const std::bad_alloc&) {
    problem = "std::bad_alloc escaped parameterize()";
  } catch (const std::exception& e) {
    problem =
        std::string("std::exception escaped parameterize(): ") + typeid(e).name() + ": " + e.what();
  } catch (...) {
    problem = "a non-std exception escaped parameterize()";
  }
  if (!problem.empty()) {
    out.problems.push_back(
        "failing allocation " +
        (index > 0 ? "#" + std::to_string(index) : ">= " + std::to_string(size) + " bytes") + ": " +
        problem);
  } else {
    (ok ? out.succeeded : out.refused) += 1;
  }
}

long countAllocations(const Mesh& m, const Options& o) {
  inject::armedRun(-1, kNoSize, [&] { parameterize(m.V, m.F, o); });
  return inject::seen.load();
}

void expectNoProblems(const InjectionOutcome& out) {
  for (size_t k = 0; k < out.problems.size() && k < 20; ++k) ADD_FAILURE() << out.problems[k];
  EXPECT_TRUE(out.problems.empty()) << out.problems.size() << " runs broke the contract";
}

TEST(CoreAllocationFailure, EveryAllocationOfASmallRunFailsCleanly) {
  const Mesh m = wavyGrid(10);
  Options o;
  o.stretch_iterations = 2;
  const long total = countAllocations(m, o);
  ASSERT_GT(total, 10);
  InjectionOutcome out;
  for (long k = 1; k <= total; ++k) runInjected(m, o, k, kNoSize, out);
  RecordProperty("allocations", static_cast<int>(total));
  EXPECT_GT(out.refused, 0);
  expectNoProblems(out);
}

// More than 5000 unknowns: the multigrid solver and its OpenMP loops. An exception thrown
// inside an OpenMP parallel region cannot leave it: it must be caught inside and passed on, or
// the process aborts (std::terminate).
TEST(CoreAllocationFailure, AllocationsOfTheMultigridSolveFailCleanly) {
  const Mesh m = test::grid(76, 1, 1, [](double x, double y) { return 0.2 * std::sin(4 * x * y); });
  const Options o = with(WeightScheme::Straightest, BoundaryShape::Circle);
  const long total = countAllocations(m, o);
  InjectionOutcome out;
  // Every allocation would take minutes; 300 spread evenly over the run reach every stage.
  const long samples = std::min<long>(total, 300);
  for (long s = 0; s < samples; ++s) runInjected(m, o, 1 + s * total / samples, kNoSize, out);
  RecordProperty("allocations", static_cast<int>(total));
  EXPECT_GT(out.refused, 0);
  expectNoProblems(out);
}

// A mesh too large for memory: its big arrays fail, small ones still succeed.
TEST(CoreAllocationFailure, LargeAllocationsFailingGiveAMemoryReason) {
  const Mesh m = test::grid(76, 1, 1, [](double x, double y) { return 0.2 * std::sin(4 * x * y); });
  InjectionOutcome out;
  for (size_t size = 1 << 10; size <= (size_t{1} << 24); size <<= 1)
    for (BoundaryShape b : kAllBoundaries)
      runInjected(m, with(WeightScheme::Straightest, b), -1, size, out);
  EXPECT_GT(out.refused, 0);
  expectNoProblems(out);
}

// sdp::measureUVs is public too (adapters measure the UVs they store with it): it "throws like
// parameterize()".
TEST(CoreAllocationFailure, MeasureUVsFailsWithAParameterizationError) {
  const Mesh m = wavyGrid(10);
  const Result r = parameterize(m.V, m.F);
  inject::armedRun(-1, kNoSize, [&] { measureUVs(m.V, m.F, r.layout.uv); });
  const long total = inject::seen.load();
  std::vector<std::string> problems;
  for (long k = 1; k <= total; ++k) {
    try {
      inject::armedRun(k, kNoSize, [&] { measureUVs(m.V, m.F, r.layout.uv); });
    } catch (const ParameterizationError&) {
    } catch (const std::exception& e) {
      problems.push_back("allocation #" + std::to_string(k) + ": " + typeid(e).name() +
                         " escaped measureUVs()");
    }
  }
  for (size_t k = 0; k < problems.size() && k < 5; ++k) ADD_FAILURE() << problems[k];
  EXPECT_TRUE(problems.empty()) << problems.size() << " of " << total << " allocations";
}

}  // namespace
}  // namespace sdp
