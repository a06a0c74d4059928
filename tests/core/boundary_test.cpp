#include <gtest/gtest.h>

#include <random>

#include "core/paper/boundary.h"
#include "core/paper/patch_topology.h"
#include "core/paper/weights.h"
#include "test_meshes.h"

namespace sdp {
namespace {

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

void expectStrictlyConvexCounterClockwise(const Polygon& p) {
  const size_t n = p.size();
  for (size_t k = 0; k < n; ++k) {
    const auto& a = p[(k + n - 1) % n];
    const auto& b = p[k];
    const auto& c = p[(k + 1) % n];
    EXPECT_GT(cross2(b - a, c - b), 0.0) << "vertex " << k << " is not strictly convex";
  }
  EXPECT_GT(polygonArea(p), 0.0);
}

TEST(Boundary, CircleIsOnTheUnitCircleInOrderWithChordSpacing) {
  const test::Mesh m = test::planarGrid(8);
  const Patch patch = buildPatch(m.V, m.F);
  const Polygon circle = circleBoundary(patch);
  ASSERT_EQ(circle.size(), patch.boundary_loop.size());
  for (const auto& q : circle) EXPECT_NEAR(q.norm(), 1.0, 1e-12);
  expectStrictlyConvexCounterClockwise(circle);
}

TEST(Boundary, SquareCornersAndSides) {
  const test::Mesh m = test::planarGrid(8);
  const Patch patch = buildPatch(m.V, m.F);
  const Polygon square = squareBoundary(patch);
  ASSERT_EQ(square.size(), patch.boundary_loop.size());
  int corners = 0;
  for (const auto& q : square) {
    const bool on_side = std::abs(q.x()) < 1e-12 || std::abs(q.x() - 1) < 1e-12 ||
                         std::abs(q.y()) < 1e-12 || std::abs(q.y() - 1) < 1e-12;
    EXPECT_TRUE(on_side);
    corners += (std::abs(q.x() - std::round(q.x())) < 1e-12 &&
                std::abs(q.y() - std::round(q.y())) < 1e-12);
  }
  EXPECT_EQ(corners, 4);
  EXPECT_NEAR(polygonArea(square), 1.0, 1e-12);
}

// A star-shaped polygon with reflex and collinear vertices becomes strictly convex, in order,
// and hull vertices do not move.
TEST(Boundary, MakeStrictlyConvexKeepsOrderAndHull) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> radius(0.5, 1.5);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 12 + trial;
    Polygon star(n);
    for (int k = 0; k < n; ++k) {
      const double a = 2 * M_PI * k / n;
      star[k] = radius(rng) * Eigen::Vector2d(std::cos(a), std::sin(a));
    }
    // three collinear points
    star[1] = 0.5 * (star[0] + star[2]);
    const Polygon convex = makeStrictlyConvex(star, std::vector<double>(n, 1.0));
    ASSERT_EQ(static_cast<int>(convex.size()), n);
    expectStrictlyConvexCounterClockwise(convex);
  }
}

// The plane walk on a flat patch measures the straight line: the Euclidean distance.
TEST(Boundary, PlaneWalkOnAPlaneIsTheEuclideanDistance) {
  const test::Mesh m = test::planarGrid(10);
  const Patch patch = buildPatch(m.V, m.F);
  const int source = patch.local_vertex[5 * 11 + 5];
  Ring ring;
  gatherRing(patch, source, ring);
  const Eigen::Vector3d normal = baseNormal(ring);
  for (int b : patch.boundary_loop) {
    const double d = planeWalkDistance(patch, source, normal, b);
    EXPECT_NEAR(d, (patch.position[b] - patch.position[source]).norm(), 1e-9);
  }
}

// On a cylinder-like bend the plane walk follows the surface, longer than the chord.
TEST(Boundary, PlaneWalkFollowsACurvedSurface) {
  const test::Mesh m =
      test::grid(20, 2.0, 2.0, [](double x, double) { return 0.5 * (x - 1) * (x - 1); });
  const Patch patch = buildPatch(m.V, m.F);
  const int source = patch.local_vertex[10 * 21 + 10];
  Ring ring;
  gatherRing(patch, source, ring);
  const Eigen::Vector3d normal = baseNormal(ring);
  const int corner_free = patch.local_vertex[10 * 21 + 20];  // (2, 1): straight along x
  const double walked = planeWalkDistance(patch, source, normal, corner_free);
  // Arc length of z = x^2/2 from 0 to 1: (sqrt(2) + asinh(1)) / 2.
  // Patch coordinates are scaled by 1 / unit (the largest extent).
  EXPECT_NEAR(walked * patch.unit, (std::sqrt(2.0) + std::asinh(1.0)) / 2, 2e-3);
}

TEST(Boundary, MeasuredBoundaryOfAPlanarPatchIsThePatchItself) {
  const test::Mesh m = test::planarGrid(12);
  const Patch patch = buildPatch(m.V, m.F);
  const int source = chooseSourceVertex(patch, SourceRule::FarthestFromBoundary);
  MeasuredCounts counts;
  const Polygon measured = measuredBoundary(patch, source, counts);
  EXPECT_EQ(counts.walk_failures, 0);
  EXPECT_EQ(counts.walk_detours, 0);
  expectStrictlyConvexCounterClockwise(measured);
  // Scaled to the 3D area (2 x 1), in patch units (1 / unit).
  EXPECT_NEAR(polygonArea(measured) * patch.unit * patch.unit, 2.0, 1e-9);
}

TEST(Boundary, SourceRules) {
  const test::Mesh m = test::planarGrid(10);
  const Patch patch = buildPatch(m.V, m.F);
  for (SourceRule rule : {SourceRule::FarthestFromBoundary, SourceRule::NearestBoundaryCentroid}) {
    const int s = chooseSourceVertex(patch, rule);
    ASSERT_GE(s, 0);
    EXPECT_FALSE(patch.on_boundary[s]);
    EXPECT_NEAR(patch.position[s].y(), 0.0, 0.051) << sourceRuleName(rule);  // mid-height row
  }
}

}  // namespace
}  // namespace sdp
