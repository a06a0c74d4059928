#include "core/refine/free_boundary.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>

#include "core/paper/patch_topology.h"
#include "core/parameterize.h"
#include "core/refine/grid_newton.h"
#include "core/refine/stretch_newton.h"
#include "core/refine/stretch_terms.h"
#include "io/mesh_io.h"
#include "test_mesh_files.h"
#include "test_meshes.h"

namespace sdp {
namespace {

// Edges of the input faces that only one face uses (all boundary loops), from F alone.
std::vector<std::pair<int, int>> borderEdges(const Triangles& F) {
  std::map<std::pair<int, int>, int> uses;
  for (int f = 0; f < F.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = F(f, c), b = F(f, (c + 1) % 3);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  std::vector<std::pair<int, int>> border;
  for (const auto& [edge, count] : uses)
    if (count == 1) border.push_back(edge);
  return border;
}

// Brute force over all pairs of border edges: any two that are not neighbours properly cross or
// touch. Independent of boundaryIsSimple's sweep.
int borderCrossings(const UVs& uv, const Triangles& F) {
  const auto border = borderEdges(F);
  auto cross = [](Eigen::Vector2d o, Eigen::Vector2d a, Eigen::Vector2d b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  int crossings = 0;
  for (size_t i = 0; i < border.size(); ++i)
    for (size_t j = i + 1; j < border.size(); ++j) {
      const auto [a, b] = border[i];
      const auto [c, d] = border[j];
      if (a == c || a == d || b == c || b == d) continue;
      const Eigen::Vector2d A = uv.row(a), B = uv.row(b), C = uv.row(c), D = uv.row(d);
      if (cross(A, B, C) * cross(A, B, D) <= 0 && cross(C, D, A) * cross(C, D, B) <= 0) ++crossings;
    }
  return crossings;
}

TEST(FreeBoundary, BoundaryIsSimpleSeesACrossing) {
  const test::Mesh m = test::planarGrid(6);
  const Patch patch = buildPatch(m.V, m.F);
  LocalUVs uv(patch.vertexCount());
  for (int v = 0; v < patch.vertexCount(); ++v) uv[v] = patch.position[v].head<2>();
  EXPECT_TRUE(boundaryIsSimple(patch, uv));
  // Pull one boundary vertex across the far side of the square: its two edges cross it.
  const int moved = patch.boundary_loop.front();
  uv[moved] = -3 * uv[moved];
  EXPECT_FALSE(boundaryIsSimple(patch, uv));
}

TEST(FreeBoundary, ClearanceSeesABorderAHairsBreadthFromItself) {
  // A notch whose two sides come within 1e-9 of each other: simple, but no float rounding keeps
  // it so; with the refinement's clearance it counts as touching.
  const LocalUVs uv = {{0, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0.5, 1e-9}, {0.4, 1}, {0, 1}};
  std::vector<BorderEdge> loop;
  for (int k = 0; k < 7; ++k) loop.push_back({k, (k + 1) % 7});
  EXPECT_TRUE(edgesAreSimple(loop, uv));
  const double clearance = borderClearance(loop, uv);
  EXPECT_NEAR(clearance, kBorderClearance * std::sqrt(2.0), 1e-15);
  EXPECT_FALSE(edgesAreSimple(loop, uv, clearance));
  // Opened to a tenth of the square, the notch keeps its clearance.
  LocalUVs open = uv;
  open[4].y() = 0.1;
  EXPECT_TRUE(edgesAreSimple(loop, open, borderClearance(loop, open)));
}

TEST(FreeBoundary, LongBordersAreSweptOnEveryCoreWithTheSameMeetings) {
  // A zigzag of 200,001 vertices (past the two-halves sort and many sweep slots) whose edges
  // never meet, then three of its vertices pulled onto other edges: exactly those meetings
  // found, wherever they fall among the slots.
  const int n = 200000;
  LocalUVs uv(n + 1);
  for (int i = 0; i <= n; ++i)
    uv[i] = {static_cast<double>(i), 2.0 * (i % 2)};  // exact: meetings too
  std::vector<BorderEdge> path;
  for (int i = 0; i < n; ++i) path.push_back({i, i + 1});
  EXPECT_TRUE(edgesAreSimple(path, uv));
  EXPECT_TRUE(verticesOfMeetingEdges(path, uv).empty());
  // Vertex k (a low one, k even) raised to lie on the edge two steps on (k + 2, k + 3): that
  // edge meets both of k's edges.
  for (int k : {10, 100000, 199990}) uv[k] = 0.5 * (uv[k + 2] + uv[k + 3]);
  EXPECT_FALSE(edgesAreSimple(path, uv));
  const std::vector<int> found = verticesOfMeetingEdges(path, uv);
  for (int k : {10, 100000, 199990})
    for (int v : {k - 1, k, k + 1, k + 2, k + 3})
      EXPECT_TRUE(std::binary_search(found.begin(), found.end(), v)) << v;
}

// camel_b: the convex boundary crushes its boundary fins (fixed-boundary L2 17); letting the
// boundary go gives them their shape back, with no fold and no boundary crossing.
// The shared mesh refined with K steps (default options otherwise), checked one-to-one here: no
// flipped face in the returned UVs, no crossing between border edges.
Result refinedAndChecked(const std::string& mesh, int steps) {
  const io::MeshData m = io::readMesh(mesh);
  Options o;
  o.stretch_iterations = steps;
  Result r = parameterize(m.V, m.F, o);
  EXPECT_EQ(r.report.flipped_faces, 0) << mesh;
  EXPECT_EQ(test::countNonPositiveFaces(r, m.F), 0) << mesh;
  EXPECT_EQ(borderCrossings(r.layout.uv, m.F), 0) << mesh;
  return r;
}

TEST(FreeBoundary, CamelBLetsTheBoundaryGoAndStaysOneToOne) {
  SDP_MESH_OR_SKIP(path, "disk/camel_b.off");
  const Result r = refinedAndChecked(path, 10);
  EXPECT_GT(r.report.free_boundary_steps, 0);
  EXPECT_LT(r.report.l2_stretch, 0.25 * r.report.l2_stretch_fixed_boundary);
}

TEST(FreeBoundary, CircleSquareAndFixedBoundaryKeepTheBoundary) {
  SDP_MESH_OR_SKIP(path, "disk/nefertiti.off");
  const io::MeshData m = io::readMesh(path);
  for (BoundaryShape shape : {BoundaryShape::Square, BoundaryShape::Circle}) {
    Options asked;
    asked.boundary = shape;
    asked.stretch_iterations = 3;
    EXPECT_EQ(parameterize(m.V, m.F, asked).report.free_boundary_steps, 0);
  }
  Options fixed;
  fixed.stretch_iterations = 3;
  fixed.free_boundary = false;
  const Result r = parameterize(m.V, m.F, fixed);
  EXPECT_EQ(r.report.free_boundary_steps, 0);
  // The same map; measured again as stored (on the input positions), so equal to rounding.
  EXPECT_NEAR(r.report.l2_stretch, r.report.l2_stretch_fixed_boundary, 1e-12);
  Options free = fixed;
  free.free_boundary = true;
  EXPECT_LT(parameterize(m.V, m.F, free).report.l2_stretch, r.report.l2_stretch);
}

// A planar patch's identity map warped smoothly in the plane (one-to-one, L2 above 1).
LocalUVs warpedInThePlane(const Patch& patch) {
  LocalUVs uv(patch.vertexCount());
  for (int v = 0; v < patch.vertexCount(); ++v) {
    const Eigen::Vector3d p = patch.position[v];
    uv[v] = Eigen::Vector2d(p.x() + 0.4 * p.x() * p.x(), p.y() * (1 + 0.5 * p.x()));
  }
  return uv;
}

// The Newton steps' result is one-to-one and `metrics` are its own.
void expectOneToOneWithItsMetrics(const Patch& patch, const LocalUVs& result,
                                  const StretchMetrics& metrics) {
  EXPECT_EQ(stretchMetrics(patch, result).l2, metrics.l2);
  EXPECT_FALSE(hasFlippedFace(patch, result));
  EXPECT_TRUE(boundaryIsSimple(patch, result));
}

// A planar patch warped in the plane: its isometric map exists and has no boundary to respect,
// so Newton steps on the L2 stretch must find it (L2 = 1) in a few steps. Checks the gradient and
// Hessian as much as the line search.
TEST(StretchNewton, UnwarpsAPlanarPatchToAnIsometry) {
  const test::Mesh m = test::planarGrid(12);
  const Patch patch = buildPatch(m.V, m.F);
  const LocalUVs uv = warpedInThePlane(patch);
  StretchMetrics metrics = stretchMetrics(patch, uv);
  ASSERT_EQ(metrics.flipped_faces, 0);
  const double before = metrics.l2;
  EXPECT_GT(before, 1.01);
  StretchNewtonCounts counts;
  const LocalUVs result = minimizeStretchWithFreeBoundary(patch, uv, 20, metrics, counts);
  EXPECT_GT(counts.steps_taken, 0);
  EXPECT_LT(metrics.l2, 1 + 1e-6);
  expectOneToOneWithItsMetrics(patch, result, metrics);
}

// camelhead: the ARAP steps stop (their optimum folds) at the fixed-boundary L2 of 1.74; the
// Newton steps on the stretch itself go on, one-to-one.
TEST(StretchNewton, CamelheadGoesOnWhereArapStops) {
  SDP_MESH_OR_SKIP(path, "disk/camelhead.off");
  const Result r = refinedAndChecked(path, 5);  // 1.78 -> 1.46
  EXPECT_LT(r.report.l2_stretch, 0.85 * r.report.l2_stretch_fixed_boundary);
}

// Above the factor's size limit the steps go on without it: conjugate gradients on the
// unassembled system, preconditioned by the multigrid, unwarp a 50k-vertex planar patch.
TEST(StretchNewton, LargePatchesStepWithoutTheFactor) {
  const int n = 224;  // (n + 1)^2 > the default direct_up_to
  const test::Mesh m = test::planarGrid(n);
  const Patch patch = buildPatch(m.V, m.F);
  ASSERT_GT(patch.real_vertex_count, StretchNewtonSettings().direct_up_to);
  const LocalUVs uv = warpedInThePlane(patch);
  StretchMetrics metrics = stretchMetrics(patch, uv);
  const double before = metrics.l2;
  ASSERT_GT(before, 1.01);
  StretchNewtonCounts counts;
  StretchNewtonSettings fine_only;  // the grid's steps have a test of their own
  fine_only.grid_max_steps = 0;
  const LocalUVs result =
      minimizeStretchWithFreeBoundary(patch, uv, 6, metrics, counts, {}, {}, fine_only);
  EXPECT_FALSE(counts.skipped);
  EXPECT_GT(counts.steps_taken, 0);
  EXPECT_GT(counts.cg_iterations, 0);
  EXPECT_LT(metrics.l2 - 1, 0.01 * (before - 1));
  expectOneToOneWithItsMetrics(patch, result, metrics);
}

// The two ways of solving the Newton system, where both run: on camelhead (11k vertices, the
// fixed-boundary map as the start; its Hessian is the worst conditioned of the shared meshes)
// 8 truncated conjugate-gradient steps take at least three quarters of the factor's L2 drop
// (measured: 85%).
TEST(StretchNewton, ConjugateGradientsMatchTheFactorOnCamelhead) {
  SDP_MESH_OR_SKIP(path, "disk/camelhead.off");
  const io::MeshData m = io::readMesh(path);
  Options fixed;
  fixed.stretch_iterations = 10;
  fixed.free_boundary = false;
  const Result start = parameterize(m.V, m.F, fixed);
  const Patch patch = buildPatch(m.V, m.F);
  LocalUVs uv(patch.vertexCount(), Eigen::Vector2d::Zero());
  for (int v = 0; v < patch.real_vertex_count; ++v)
    uv[v] = start.layout.uv.row(patch.input_vertex[v]).transpose();
  const StretchMetrics begin = stretchMetrics(patch, uv);
  ASSERT_EQ(begin.flipped_faces, 0);
  double l2[2];
  for (int direct = 0; direct < 2; ++direct) {
    StretchNewtonSettings settings;
    settings.direct_up_to = direct ? 1 << 30 : 0;
    settings.grid_max_steps = 0;
    StretchMetrics metrics = begin;
    StretchNewtonCounts counts;
    const LocalUVs result =
        minimizeStretchWithFreeBoundary(patch, uv, 8, metrics, counts, {}, {}, settings);
    EXPECT_GT(counts.steps_taken, 0);
    EXPECT_EQ(counts.cg_iterations > 0, !direct);
    EXPECT_FALSE(hasFlippedFace(patch, result));
    EXPECT_TRUE(boundaryIsSimple(patch, result));
    l2[direct] = metrics.l2;
  }
  EXPECT_LT(l2[1], 0.9 * begin.l2);
  EXPECT_GT(begin.l2 - l2[0], 0.75 * (begin.l2 - l2[1]));
}

// The grid's steps (grid_newton.h) alone: a smooth warp of a planar patch is a smooth deformation
// of the plane, which the grid's space holds up to its resolution, so its steps remove most of
// the stretch, one-to-one, before any fine step.
TEST(StretchNewton, GridStepsUnwarpASmoothWarp) {
  const test::Mesh m = test::planarGrid(60);
  const Patch patch = buildPatch(m.V, m.F);
  const LocalUVs uv = warpedInThePlane(patch);
  StretchMetrics metrics = stretchMetrics(patch, uv);
  const double before = metrics.l2;
  ASSERT_GT(before, 1.01);
  StretchNewtonSettings settings;
  settings.direct_up_to = 100;  // the large-patch path on a small patch
  settings.grid.cells = 16;
  StretchNewtonCounts counts;
  const LocalUVs result =
      minimizeStretchWithFreeBoundary(patch, uv, 1, metrics, counts, {}, {}, settings);
  EXPECT_GT(counts.grid_steps, 2);
  EXPECT_LT(metrics.l2 - 1, 0.05 * (before - 1));
  expectOneToOneWithItsMetrics(patch, result, metrics);
}

// The grid's system with the Hessian of faces across cell edges carried as if each lay in its
// corners' cells (GridNewtonSettings::exact_below) against the exact one, on a smooth warp
// where no face is stiff: the same gradient, so its direction still descends, and a system
// coupled only within cells, whose factor costs less; the same at any scale of the map.
TEST(StretchNewton, GridHessianWithinCellsDescendsAndFactorsCheaper) {
  const test::Mesh m = test::planarGrid(60);
  const Patch patch = buildPatch(m.V, m.F);
  std::vector<FaceFrame> frames(patch.real_face_count);
  for (int f = 0; f < patch.real_face_count; ++f) frames[f] = faceFrame(patch, f, 0);
  for (const double scale : {1.0, 1e-3}) {
    LocalUVs uv = warpedInThePlane(patch);
    for (Eigen::Vector2d& p : uv) p *= scale;
    const Energy energy = energyOf(patch, frames, uv);
    double slope[2], work[2];
    Eigen::VectorXd direction[2];
    for (int exact = 0; exact < 2; ++exact) {
      GridNewtonSettings settings;
      settings.cells = 16;
      if (exact) settings.exact_below = 1e9;  // every face stiff: the exact carry
      GridNewtonSystem grid(patch, frames, settings);
      direction[exact].resize(2 * patch.real_vertex_count);
      ASSERT_TRUE(grid.solve(uv, energy, direction[exact]));
      slope[exact] = grid.slope();
      work[exact] = grid.lastWork();
    }
    EXPECT_LT(slope[0], 0) << scale;
    EXPECT_LT(work[0], work[1]) << scale;
    // Near the exact direction: the approximation changes the Hessian only on the cells' edges.
    EXPECT_GT(direction[0].dot(direction[1]), 0.9 * direction[0].norm() * direction[1].norm())
        << scale;
    // A short step along it lowers the energy.
    LocalUVs moved = uv;
    const double step = 0.1;
    for (int v = 0; v < patch.real_vertex_count; ++v)
      moved[v] += step * direction[0].segment<2>(2 * v);
    EXPECT_LT(energyOf(patch, frames, moved).value(), energy.value()) << scale;
  }
}

// The projected Hessian of |J|^2 / det^2 + w det from its known eigensystem equals an
// eigensolver's projection of the exact Hessian (differentiated twice by hand below), also where
// the singular values are equal (a rotation times a scale) and far apart, for area weights w
// from none to large.
TEST(StretchNewton, AnalyticHessianMatchesTheEigensolversProjection) {
  const auto exact = [](const Eigen::Vector4d& J, double w) {
    const double det = J[0] * J[3] - J[1] * J[2], fro = J.squaredNorm();
    const Eigen::Vector4d cof(J[3], -J[2], -J[1], J[0]);
    const double q2 = det * det, q3 = q2 * det, q4 = q2 * q2;
    Eigen::Matrix4d h = (2 / q2) * Eigen::Matrix4d::Identity() -
                        (4 / q3) * (J * cof.transpose() + cof * J.transpose()) +
                        (6 * fro / q4) * cof * cof.transpose();
    h(0, 3) -= 2 * fro / q3;
    h(3, 0) -= 2 * fro / q3;
    h(1, 2) += 2 * fro / q3;
    h(2, 1) += 2 * fro / q3;
    // det = ad - bc
    h(0, 3) += w;
    h(3, 0) += w;
    h(1, 2) -= w;
    h(2, 1) -= w;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(h);
    const Eigen::Vector4d clamped = eigen.eigenvalues().cwiseMax(1e-8 / q2);
    return Eigen::Matrix4d(eigen.eigenvectors() * clamped.asDiagonal() *
                           eigen.eigenvectors().transpose());
  };
  std::vector<Eigen::Vector4d> cases = {
      {1, 0, 0, 1}, {0.6, -0.8, 0.8, 0.6}, {2, 0, 0, 2}, {3, 0.1, -0.2, 0.05}, {0.01, 2, -3, 0.02}};
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  while (cases.size() < 200) {
    Eigen::Vector4d J(normal(random), normal(random), normal(random), normal(random));
    if (J[0] * J[3] - J[1] * J[2] < 0) J.head<2>() *= -1;
    cases.push_back(J);
  }
  for (const double w : {0.0, 0.5, 3.4, 40.0})
    for (const Eigen::Vector4d& J : cases) {
      const Eigen::Matrix4d expected = exact(J, w), got = stretchHessian(J, w);
      EXPECT_LT((got - expected).norm(), 1e-9 * expected.norm()) << J.transpose() << " w " << w;
    }
}

// With holes every loop is checked: no hole may cross another or the outer loop.
TEST(FreeBoundary, HolesStayApart) {
  SDP_MESH_OR_SKIP(path, "holes/beetle.off");
  const Result r = refinedAndChecked(path, 3);
  EXPECT_LE(r.report.l2_stretch, r.report.l2_stretch_fixed_boundary);
}

}  // namespace
}  // namespace sdp
