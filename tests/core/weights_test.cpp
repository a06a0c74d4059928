#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "core/paper/patch_topology.h"
#include "core/paper/weights.h"
#include "test_meshes.h"

namespace sdp {
namespace {

const WeightScheme kAllSchemes[] = {WeightScheme::Straightest, WeightScheme::Ltd,
                                    WeightScheme::Floater, WeightScheme::MeanValue,
                                    WeightScheme::Uniform};

std::vector<double> centreWeights(const test::Mesh& m, WeightScheme scheme, WeightCounts& counts) {
  const Patch patch = buildPatch(m.V, m.F);
  const std::vector<double> all = computeWeights(patch, scheme, counts);
  const int centre = patch.local_vertex[0];
  return {all.begin() + patch.ring_begin[centre], all.begin() + patch.ring_begin[centre + 1]};
}

// A regular ring is symmetric, so every scheme must give every neighbour 1/n -- in the plane
// and with the centre lifted off it (a cone).
TEST(Weights, RegularRingGivesEqualWeightsForEveryScheme) {
  for (int n : {3, 5, 6, 7, 10})
    for (double lift : {0.0, 0.4})
      for (WeightScheme scheme : kAllSchemes) {
        WeightCounts counts;
        const auto w = centreWeights(test::regularFan(n, lift), scheme, counts);
        ASSERT_EQ(static_cast<int>(w.size()), n);
        for (double x : w)
          EXPECT_NEAR(x, 1.0 / n, 1e-12)
              << weightSchemeName(scheme) << " n=" << n << " lift=" << lift;
        EXPECT_EQ(counts.straightest_to_ltd, 0);
        EXPECT_EQ(counts.degenerate_rings, 0);
      }
}

// On a planar ring, the geometric schemes reproduce the centre from its neighbours (linear
// precision): this is what makes a planar patch map to itself.
TEST(Weights, PlanarIrregularRingReproducesTheCentre) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> radius(0.3, 2.0), jitter(-0.25, 0.25);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 4 + trial % 6;
    test::Mesh m = test::regularFan(n);
    for (int k = 1; k <= n; ++k) {
      const double a = 2 * M_PI * (k - 1 + jitter(rng)) / n, r = radius(rng);
      m.V.row(k) << r * std::cos(a), r * std::sin(a), 0;
    }
    for (WeightScheme scheme : {WeightScheme::Straightest, WeightScheme::Ltd, WeightScheme::Floater,
                                WeightScheme::MeanValue}) {
      WeightCounts counts;
      const auto w = centreWeights(m, scheme, counts);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      double total = 0;
      for (int k = 0; k < n; ++k) {
        EXPECT_GE(w[k], 0.0);
        sum += w[k] * m.V.row(k + 1).transpose();
        total += w[k];
      }
      EXPECT_NEAR(total, 1.0, 1e-12);
      EXPECT_NEAR(sum.norm(), 0.0, 1e-9) << weightSchemeName(scheme) << " trial " << trial;
    }
  }
}

// The paper's rule when the cutting plane crosses several far-side edges: the crossing most
// opposite to V_j (smallest cosine with its in-plane direction) is used.
TEST(Weights, CuttingPlanePicksTheMostOppositeFarSideCrossing) {
  Ring ring;
  ring.center = Eigen::Vector3d::Zero();
  // A ring that zig-zags back and forth across the far side of the plane y = 0 (possible on a
  // real 3D surface: its projection is not star-shaped), so P crosses several far-side edges.
  const double xyz[][3] = {{1, 0, 0},         {0.5, 0.8, 0},     {-0.3, 0.9, 0},
                           {-1.0, 0.3, 0.2},  {-0.7, -0.2, 0.0}, {-0.5, 0.25, -0.2},
                           {-0.8, -0.4, 0.1}, {-0.2, -0.9, 0},   {0.6, -0.7, 0}};
  for (const auto& q : xyz) ring.neighbour.emplace_back(q[0], q[1], q[2]);
  ASSERT_TRUE(prepareRing(ring));
  const Eigen::Vector3d normal = baseNormal(ring);
  RingExit exit;
  ASSERT_TRUE(cuttingPlaneExit(ring, normal, 0, exit));
  // Brute force over all crossings of the same plane.
  Eigen::Vector3d t = ring.neighbour[0] - ring.neighbour[0].dot(normal) * normal;
  t.normalize();
  const Eigen::Vector3d plane = t.cross(normal).normalized();
  double best = 0;
  int crossings = 0;
  for (int a = 1; a < 8; ++a) {
    const double da = plane.dot(ring.neighbour[a]), db = plane.dot(ring.neighbour[a + 1]);
    if ((da > 0) == (db > 0)) continue;
    const Eigen::Vector3d x =
        ring.neighbour[a] + da / (da - db) * (ring.neighbour[a + 1] - ring.neighbour[a]);
    const double cosine = x.dot(t) / x.norm();
    if (cosine < 0) ++crossings;
    best = std::min(best, cosine);
  }
  EXPECT_GE(crossings, 2);
  const Eigen::Vector3d chosen =
      (1 - exit.s) * ring.neighbour[exit.a] + exit.s * ring.neighbour[(exit.a + 1) % 9];
  EXPECT_NEAR(chosen.dot(t) / chosen.norm(), best, 1e-12);
  EXPECT_NEAR(chosen.norm(), exit.d2, 1e-12);
}

TEST(Weights, DegenerateRingFallsBackToUniformAndIsCounted) {
  test::Mesh m = test::regularFan(6);
  m.V.row(2) = m.V.row(1);  // face (0, 1, 2) has zero area
  for (WeightScheme scheme :
       {WeightScheme::Straightest, WeightScheme::Floater, WeightScheme::MeanValue}) {
    WeightCounts counts;
    const auto w = centreWeights(m, scheme, counts);
    EXPECT_EQ(counts.degenerate_rings, 1) << weightSchemeName(scheme);
    for (double x : w) EXPECT_DOUBLE_EQ(x, 1.0 / 6);
  }
}

TEST(Weights, AllWeightsFiniteNonNegativeAndRowsSumToOne) {
  const test::Mesh m = test::grid(
      12, 1.0, 1.0, [](double x, double y) { return 0.3 * std::sin(6 * x) * std::cos(5 * y); });
  const Patch patch = buildPatch(m.V, m.F);
  for (WeightScheme scheme : kAllSchemes) {
    WeightCounts counts;
    const auto w = computeWeights(patch, scheme, counts);
    for (int v = 0; v < patch.vertexCount(); ++v) {
      if (patch.on_boundary[v]) continue;
      double sum = 0;
      for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k) {
        ASSERT_TRUE(std::isfinite(w[k]));
        ASSERT_GE(w[k], 0.0);
        sum += w[k];
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
    }
  }
}

}  // namespace
}  // namespace sdp
